#include "kernels/wilson/hybrid_slicer.h"

#include "kernels/wilson/slice_frame_builder.h"

#include <algorithm>
#include <cmath>

namespace pp5 {

HybridSlicer::HybridSlicer(const WilsonSettings& settings, const RegionMachine& machine, const HybridVolume& hybrid,
                           glm::vec3 spacing)
    : settings_(settings),
      machine_(machine),
      hybrid_(&hybrid),
      spacing_(spacing),
      bricks_((hybrid.low_resolution().dims() + settings.brick_voxels - 1) / settings.brick_voxels),
      format_{settings.accumulator_bits},
      programs_(format_, machine.local_memory_bits) {}

std::uint32_t HybridSlicer::brick_of(const HybridPoint& point) const {
    const glm::vec3 position = hybrid_->position(point);
    const glm::ivec3 n = hybrid_->low_resolution().dims();
    const float k = static_cast<float>(hybrid_->factor());
    glm::ivec3 texel;
    for (int axis = 0; axis < 3; ++axis)
        texel[axis] = std::clamp(static_cast<int>(std::floor((position[axis] + 0.5f) / k)), 0, n[axis] - 1);
    const glm::ivec3 bc = texel / settings_.brick_voxels;
    return static_cast<std::uint32_t>(bc.x + bricks_.x * (bc.y + bricks_.y * bc.z));
}

std::vector<std::uint64_t> HybridSlicer::resident_bits_by_brick() const {
    std::vector<std::uint64_t> bits(
        static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y) * static_cast<std::size_t>(bricks_.z),
        0);
    const auto record_bits = 8 * static_cast<std::uint64_t>(hybrid_->point_format().record_bytes());
    for (const HybridPoint& p : hybrid_->points()) bits[brick_of(p)] += record_bits;
    return bits;
}

HybridFrame HybridSlicer::render(const ShadedCodes& texels, const PointLook& look, const Camera& camera, int width,
                                 int height, glm::vec3 background) const {
    return slicing::FrameBuilder(*this, settings_, machine_, *hybrid_, spacing_, bricks_, format_, programs_, texels,
                                 look, camera, width, height, background)
        .build();
}

}  // namespace pp5
