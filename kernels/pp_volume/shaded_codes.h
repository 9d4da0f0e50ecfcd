#pragma once
// The colours and opacities the pixel processors hold, as the codes of their backing stores: what the
// GPs fetch and what the kernels' host renderers read. A channel's value is its code over the
// channel's largest code (2^bits - 1), the PPs' own fixed-point meaning.
//
// Keeping the codes instead of floats takes 8 bytes a voxel instead of 16 (134 MB less at 256^3), and
// loses nothing: a reader decodes each voxel with the same float division the PPs' read-out would
// have done, so every sample, and every picture, is bit for bit what a float copy would give.

#include "kernels/reference/shaded_volume.h"

#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <vector>

namespace pp5 {

struct ShadedCodes {
    glm::ivec3 dims{0};
    glm::vec3 spacing{1.0f};
    glm::vec4 code_max{1.0f};          // per channel (r, g, b, opacity): the code that means 1
    std::vector<glm::u16vec4> codes;   // Volume::index order

    glm::vec4 value(std::size_t voxel) const { return glm::vec4(codes[voxel]) / code_max; }
    bool transparent(std::size_t voxel) const { return codes[voxel].a == 0; }
    // Every voxel decoded: a float volume for the reference compositor and for tests.
    ShadedVolume decoded() const;
};

}  // namespace pp5
