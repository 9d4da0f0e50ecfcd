#include "kernels/shared/pp_volume/shaded_codes.h"

#include <stdexcept>

namespace pp5 {

ShadedCodes::ShadedCodes(glm::ivec3 dims, glm::vec3 spacing, glm::vec4 code_max) { reset(dims, spacing, code_max); }

void ShadedCodes::reset(glm::ivec3 dims, glm::vec3 spacing, glm::vec4 code_max) {
    for (int c = 0; c < 4; ++c)
        if (!(code_max[c] >= 1.0f && code_max[c] <= 65535.0f))
            throw std::invalid_argument("shaded codes: a channel of 1 to 16 bits");
    const std::size_t voxels =
        static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
    dims_ = dims;
    spacing_ = spacing;
    code_max_ = code_max;
    narrow_storage_ = code_max.r <= 255.0f && code_max.g <= 255.0f && code_max.b <= 255.0f && code_max.a <= 255.0f;
    if (narrow_storage_) {
        wide_ = {};
        narrow_.resize(voxels);
    } else {
        narrow_ = {};
        wide_.resize(voxels);
    }
}

ShadedVolume ShadedCodes::decoded() const {
    ShadedVolume volume;
    volume.dims = dims_;
    volume.spacing = spacing_;
    volume.rgba.resize(size());
    for (std::size_t i = 0; i < volume.rgba.size(); ++i) volume.rgba[i] = value(i);
    return volume;
}

}  // namespace pp5
