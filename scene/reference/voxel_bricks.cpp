#include "scene/reference/voxel_bricks.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>

#include <stdexcept>

namespace pp5 {

VoxelBricks::VoxelBricks(const Volume& volume, const GradientField& gradients) : volume_dims_(volume.dims()) {
    if (gradients.dims != volume.dims()) throw std::invalid_argument("VoxelBricks: gradients of another volume");
    const OccupancyGrid layout(volume.dims());
    const glm::ivec3 blocks = layout.block_dims();
    auto block_at = [&](std::size_t i) {
        const std::size_t nx = static_cast<std::size_t>(blocks.x);
        const std::size_t ny = static_cast<std::size_t>(blocks.y);
        return glm::ivec3(static_cast<int>(i % nx), static_cast<int>((i / nx) % ny), static_cast<int>(i / (nx * ny)));
    };
    offsets_.resize(layout.block_count() + 1, 0);
    for (std::size_t i = 0; i < layout.block_count(); ++i) {
        const glm::ivec3 size = layout.last_voxel(block_at(i)) - layout.first_voxel(block_at(i)) + 1;
        offsets_[i + 1] = offsets_[i] + static_cast<std::size_t>(size.x) * static_cast<std::size_t>(size.y) *
                                            static_cast<std::size_t>(size.z);
    }
    data_.resize(offsets_.back());
    refill(volume, gradients);
}

void VoxelBricks::refill(const Volume& volume, const GradientField& gradients) {
    if (volume.dims() != volume_dims_ || gradients.dims != volume_dims_)
        throw std::invalid_argument("VoxelBricks::refill: another volume's voxels");
    const std::span<const float> values = volume.samples();
    for_each_voxel([&](std::size_t out, std::size_t i) { data_[out] = glm::vec4(gradients.at(i), values[i]); });
}

template <class Visit>
void VoxelBricks::for_each_voxel(Visit&& visit) const {
    const OccupancyGrid layout(volume_dims_);
    const glm::ivec3 blocks = layout.block_dims();
    const std::size_t row = static_cast<std::size_t>(volume_dims_.x);
    const std::size_t slice = row * static_cast<std::size_t>(volume_dims_.y);
    pp5::parallel_for(
        tbb::blocked_range<std::size_t>(0, layout.block_count()), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t b = r.begin(); b != r.end(); ++b) {
                const std::size_t nx = static_cast<std::size_t>(blocks.x);
                const std::size_t ny = static_cast<std::size_t>(blocks.y);
                const glm::ivec3 block(static_cast<int>(b % nx), static_cast<int>((b / nx) % ny),
                                       static_cast<int>(b / (nx * ny)));
                const glm::ivec3 lo = layout.first_voxel(block);
                const glm::ivec3 hi = layout.last_voxel(block);
                std::size_t out = offsets_[b];
                for (int z = lo.z; z <= hi.z; ++z) {
                    for (int y = lo.y; y <= hi.y; ++y) {
                        std::size_t i = static_cast<std::size_t>(lo.x) + row * static_cast<std::size_t>(y) +
                                        slice * static_cast<std::size_t>(z);
                        for (int x = lo.x; x <= hi.x; ++x, ++i, ++out) visit(out, i);
                    }
                }
            }
        });
}

std::vector<float> VoxelBricks::gather(std::span<const float> per_voxel) const {
    if (per_voxel.size() != static_cast<std::size_t>(volume_dims_.x) * static_cast<std::size_t>(volume_dims_.y) *
                                static_cast<std::size_t>(volume_dims_.z)) {
        throw std::invalid_argument("VoxelBricks::gather: one value per voxel");
    }
    std::vector<float> bricked(data_.size());
    for_each_voxel([&](std::size_t out, std::size_t i) { bricked[out] = per_voxel[i]; });
    return bricked;
}

}  // namespace pp5
