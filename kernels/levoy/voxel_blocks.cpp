#include "kernels/levoy/voxel_blocks.h"

#include <glm/common.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pp5 {

namespace {
constexpr std::uint32_t kUnknown = std::numeric_limits<std::uint32_t>::max();
}

VoxelBlocks::VoxelBlocks(const VoxelPlacement& placement, int block_cells, int voxel_bits)
    : placement_(placement), block_cells_(block_cells), voxel_bits_(voxel_bits) {
    if (block_cells < 1 || voxel_bits < 1) throw std::invalid_argument("voxel blocks: sizes must be positive");
    const glm::ivec3 cells = placement.volume_dims() - 1;
    blocks_ = (glm::max(cells, glm::ivec3(1)) + block_cells - 1) / block_cells;
    const auto count = block_count();
    if (count >= kUnknown) throw std::invalid_argument("voxel blocks: too many blocks; use larger ones");
    const glm::ivec3 stride{1, blocks_.x, blocks_.x * blocks_.y};
    std::vector<std::uint32_t>* parts[3] = {&x_part_, &y_part_, &z_part_};
    for (int a = 0; a < 3; ++a) {
        parts[a]->resize(static_cast<std::size_t>(std::max(cells[a], 1)));
        for (int c = 0; c < std::max(cells[a], 1); ++c)
            (*parts[a])[static_cast<std::size_t>(c)] = static_cast<std::uint32_t>((c / block_cells) * stride[a]);
    }
    first_part_.assign(count, kUnknown);
    part_count_.assign(count, 0);
}

std::uint64_t VoxelBlocks::block_bits() const {
    const auto side = static_cast<std::uint64_t>(block_cells_ + 1);
    return side * side * side * static_cast<std::uint64_t>(voxel_bits_);
}

std::span<const VoxelBlocks::Part> VoxelBlocks::parts(std::uint32_t block) {
    if (first_part_.at(block) == kUnknown) {
        const glm::ivec3 b{static_cast<int>(block % static_cast<std::uint32_t>(blocks_.x)),
                           static_cast<int>(block / static_cast<std::uint32_t>(blocks_.x) % static_cast<std::uint32_t>(blocks_.y)),
                           static_cast<int>(block / static_cast<std::uint32_t>(blocks_.x * blocks_.y))};
        const glm::ivec3 lo = b * block_cells_;
        const glm::ivec3 hi = glm::min(lo + block_cells_, placement_.volume_dims() - 1);  // inclusive
        const int columns = placement_.shape().columns;
        const int rows = placement_.shape().rows;
        // Within one z and one tile of PP columns x rows, every voxel is on the same renderer.
        std::vector<std::pair<int, std::uint32_t>> by_renderer;  // few entries: a linear search beats a map
        for (int z = lo.z; z <= hi.z; ++z) {
            for (int y = lo.y; y <= hi.y; y = (y / rows + 1) * rows) {
                const int y_end = std::min(hi.y + 1, (y / rows + 1) * rows);
                for (int x = lo.x; x <= hi.x; x = (x / columns + 1) * columns) {
                    const int x_end = std::min(hi.x + 1, (x / columns + 1) * columns);
                    const int renderer = placement_.locate({x, y, z}).renderer;
                    const auto voxels = static_cast<std::uint32_t>((x_end - x) * (y_end - y));
                    const auto it = std::find_if(by_renderer.begin(), by_renderer.end(), [&](const auto& e) { return e.first == renderer; });
                    if (it == by_renderer.end()) by_renderer.emplace_back(renderer, voxels);
                    else it->second += voxels;
                }
            }
        }
        first_part_[block] = static_cast<std::uint32_t>(parts_.size());
        part_count_[block] = static_cast<std::uint16_t>(by_renderer.size());
        std::sort(by_renderer.begin(), by_renderer.end());  // renderer order, as the requests go out
        for (const auto& [renderer, voxels] : by_renderer) parts_.push_back(Part{renderer, voxels});
    }
    return {parts_.data() + first_part_[block], part_count_[block]};
}

std::shared_ptr<const BlockDirectory> VoxelBlocks::directory() {
    std::vector<std::uint32_t> first{0};
    std::vector<BlockPart> all;
    for (std::uint64_t b = 0; b < block_count(); ++b) {
        for (const Part& part : parts(static_cast<std::uint32_t>(b)))
            all.push_back(BlockPart{static_cast<std::uint32_t>(part.renderer), part.voxels});
        first.push_back(static_cast<std::uint32_t>(all.size()));
    }
    return std::make_shared<const BlockDirectory>(block_bits(), static_cast<std::uint32_t>(voxel_bits_), std::move(first), std::move(all));
}

}  // namespace pp5
