#include "kernels/shared/pp_volume/voxel_record.h"

#include <algorithm>
#include <cmath>

namespace pp5 {

VoxelQuantization VoxelQuantization::choose(const Volume& volume, const VoxelRecordLayout& layout) {
    return for_ranges(volume.min_value(), volume.max_value(), is_integer_type(volume.source_type()),
                      largest_gradient_component(volume), layout);
}

VoxelQuantization VoxelQuantization::for_ranges(float value_min, float value_max, bool integer_values,
                                                float largest_gradient, const VoxelRecordLayout& layout) {
    VoxelQuantization q;
    q.value_max_code = static_cast<int>((std::int64_t{1} << layout.value_bits) - 1);
    q.gradient_max_code = static_cast<int>((std::int64_t{1} << (layout.gradient_bits - 1)) - 1);
    q.value_offset = value_min;
    const float range = value_max - value_min;
    const bool exact = integer_values && range <= static_cast<float>(q.value_max_code);
    q.value_scale = exact || range <= 0.0f ? 1.0f : static_cast<float>(q.value_max_code) / range;
    q.gradient_scale = largest_gradient > 0.0f ? static_cast<float>(q.gradient_max_code) / largest_gradient : 1.0f;
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
