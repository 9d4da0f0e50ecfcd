#include "scene/reference/shaded_volume.h"

#include "scene/reference/polygon_matte.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>

#include <atomic>
#include <stdexcept>

namespace pp5 {

namespace {

void check_inputs(const Volume& volume, const GradientField& gradients, std::span<const float> opacities) {
    if (gradients.dims != volume.dims()) throw std::invalid_argument("shade_voxels: gradients of another volume");
    if (opacities.size() != volume.voxel_count())
        throw std::invalid_argument("shade_voxels: opacities of another volume");
}

}  // namespace

BlockShader::BlockShader(const Volume& volume, const GradientField& gradients, std::span<const float> opacities,
                         const OccupancyGrid& occupancy, const ColorMap& color_map, const PhongLighting& lighting,
                         const ShadingView& view, const VoxelBricks* bricks, std::span<const float> brick_opacities,
                         const PolygonMattes* mattes)
    : volume_(volume),
      gradients_(gradients),
      opacities_(opacities),
      occupancy_(occupancy),
      shader_(color_map, lighting, view, volume.spacing()),
      bricks_(bricks),
      brick_opacities_(brick_opacities),
      mattes_(mattes) {
    check_inputs(volume, gradients, opacities);
    if (occupancy.volume_dims() != volume.dims())
        throw std::invalid_argument("BlockShader: occupancy of another volume");
    if (bricks != nullptr && (bricks->volume_dims() != volume.dims() || brick_opacities.size() != opacities.size())) {
        throw std::invalid_argument("BlockShader: bricks of another volume");
    }
}

std::uint64_t BlockShader::shade(glm::ivec3 block, ShadedVolume& out) const {
    const glm::ivec3 lo = occupancy_.first_voxel(block);
    const glm::ivec3 hi = occupancy_.last_voxel(block);
    const glm::vec3 spacing = volume_.spacing();
    if (bricks_ != nullptr) {
        const std::size_t b = occupancy_.block_index(block);
        const glm::vec4* in = bricks_->brick(b).data();
        const float* opacity = brick_opacities_.data() + bricks_->offset(b);
        for (int z = lo.z; z <= hi.z; ++z) {
            for (int y = lo.y; y <= hi.y; ++y) {
                std::size_t i = volume_.index(lo.x, y, z);
                for (int x = lo.x; x <= hi.x; ++x, ++i, ++in, ++opacity) {
                    const glm::vec3 position = glm::vec3(x, y, z) * spacing;
                    out.rgba[i] = glm::vec4(shader_.shade(in->w, glm::vec3(*in), position), *opacity);
                }
            }
        }
    } else {
        const std::span<const float> values = volume_.samples();
        for (int z = lo.z; z <= hi.z; ++z) {
            for (int y = lo.y; y <= hi.y; ++y) {
                std::size_t i = volume_.index(lo.x, y, z);
                for (int x = lo.x; x <= hi.x; ++x, ++i) {
                    const glm::vec3 position = glm::vec3(x, y, z) * spacing;
                    out.rgba[i] = glm::vec4(shader_.shade(values[i], gradients_.at(i), position), opacities_[i]);
                }
            }
        }
    }
    if (mattes_ != nullptr) mattes_->apply(occupancy_.block_index(block), out);
    const glm::ivec3 size = hi - lo + 1;
    return static_cast<std::uint64_t>(size.x) * static_cast<std::uint64_t>(size.y) * static_cast<std::uint64_t>(size.z);
}

std::uint64_t reshade_voxels(ShadedVolume& shaded, const Volume& volume, const GradientField& gradients,
                             std::span<const float> opacities, const OccupancyGrid& occupancy,
                             const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view) {
    if (shaded.dims != volume.dims() || shaded.rgba.size() != volume.voxel_count()) {
        throw std::invalid_argument("reshade_voxels: shaded volume of another volume");
    }
    const BlockShader shader(volume, gradients, opacities, occupancy, color_map, lighting, view);
    const std::vector<glm::ivec3> blocks = occupancy.occupied_blocks();
    std::atomic<std::uint64_t> shaded_count{0};
    pp5::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        std::uint64_t count = 0;
        for (std::size_t b = r.begin(); b != r.end(); ++b) count += shader.shade(blocks[b], shaded);
        shaded_count += count;
    });
    return shaded_count;
}

ShadedVolume shade_voxels(const Volume& volume, const GradientField& gradients, std::span<const float> opacities,
                          const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view,
                          const OccupancyGrid* occupancy) {
    check_inputs(volume, gradients, opacities);
    ShadedVolume shaded;
    shaded.dims = volume.dims();
    shaded.spacing = volume.spacing();
    shaded.rgba.assign(volume.voxel_count(), glm::vec4(0.0f));
    if (occupancy != nullptr) {
        reshade_voxels(shaded, volume, gradients, opacities, *occupancy, color_map, lighting, view);
    } else {
        const OccupancyGrid computed = occupancy_from_opacity(volume.dims(), opacities);
        reshade_voxels(shaded, volume, gradients, opacities, computed, color_map, lighting, view);
    }
    return shaded;
}

ShadedVolume shade_voxels(const Volume& volume, const GradientField& gradients, std::span<const float> opacities,
                          const ColorMap& color_map, const PhongLighting& lighting, const Camera& camera,
                          const OccupancyGrid* occupancy) {
    return shade_voxels(volume, gradients, opacities, color_map, lighting,
                        make_shading_view(camera, volume.dims(), volume.spacing()), occupancy);
}

}  // namespace pp5
