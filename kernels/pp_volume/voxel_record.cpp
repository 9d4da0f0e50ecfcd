#include "kernels/pp_volume/voxel_record.h"

#include <algorithm>
#include <cmath>

namespace pp5 {

namespace {

bool is_integer_type(ScalarType type) {
    return type != ScalarType::Float32 && type != ScalarType::Float64;
}

}  // namespace

VoxelQuantization VoxelQuantization::choose(const Volume& volume, const GradientField& gradients,
                                            const VoxelRecordLayout& layout) {
    VoxelQuantization q;
    q.value_max_code = static_cast<int>((std::int64_t{1} << layout.value_bits) - 1);
    q.gradient_max_code = static_cast<int>((std::int64_t{1} << (layout.gradient_bits - 1)) - 1);
    q.value_offset = volume.min_value();
    const float range = volume.max_value() - volume.min_value();
    const bool exact = is_integer_type(volume.source_type()) && range <= static_cast<float>(q.value_max_code);
    q.value_scale = exact || range <= 0.0f ? 1.0f : static_cast<float>(q.value_max_code) / range;

    float largest = 0.0f;
    for (const glm::vec3& g : gradients.gradients) largest = std::max({largest, std::abs(g.x), std::abs(g.y), std::abs(g.z)});
    q.gradient_scale = largest > 0.0f ? static_cast<float>(q.gradient_max_code) / largest : 1.0f;
    return q;
}

std::int64_t VoxelQuantization::value_code(float f) const {
    const auto code = static_cast<std::int64_t>(std::lround((f - value_offset) * value_scale));
    return std::clamp<std::int64_t>(code, 0, value_max_code);
}

std::int64_t VoxelQuantization::gradient_code(float g) const {
    const auto code = static_cast<std::int64_t>(std::lround(g * gradient_scale));
    return std::clamp<std::int64_t>(code, -gradient_max_code, gradient_max_code);
}

}  // namespace pp5
