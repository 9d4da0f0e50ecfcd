#pragma once
// The colours and opacities the pixel processors hold, as the codes of their backing stores: what the
// GPs fetch and what the kernels' host renderers read. A channel's value is its code over the
// channel's largest code (2^bits - 1), the PPs' own fixed-point meaning.
//
// Keeping the codes instead of floats takes 4 bytes a voxel (8 when a channel has more than 8 bits)
// instead of 16, 201 MB less at 256^3, and loses nothing: a reader decodes each voxel with the same
// float division the PPs' read-out would have done, so every sample, and every picture, is bit for
// bit what a float copy would give.

#include "scene/reference/shaded_volume.h"

#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <vector>

namespace pp5 {

class ShadedCodes {
public:
    ShadedCodes() = default;
    // Every voxel transparent and black, stored in 8 bits a channel when `code_max` allows it.
    ShadedCodes(glm::ivec3 dims, glm::vec3 spacing, glm::vec4 code_max);
    // Keeps the storage when the size and width are unchanged (a reshade).
    void reset(glm::ivec3 dims, glm::vec3 spacing, glm::vec4 code_max);

    glm::ivec3 dims() const { return dims_; }
    glm::vec3 spacing() const { return spacing_; }
    glm::vec4 code_max() const { return code_max_; }
    std::size_t size() const { return narrow() ? narrow_.size() : wide_.size(); }
    // One of these holds the codes, in Volume::index order: 8 bits a channel, or 16.
    bool narrow() const { return narrow_storage_; }
    const glm::u8vec4* narrow_codes() const { return narrow_.data(); }
    glm::u8vec4* narrow_codes_to_write() { return narrow_.data(); }
    const glm::u16vec4* wide_codes() const { return wide_.data(); }

    glm::u16vec4 code(std::size_t voxel) const { return narrow() ? glm::u16vec4(narrow_[voxel]) : wide_[voxel]; }
    void set(std::size_t voxel, glm::u16vec4 code) {
        if (narrow()) narrow_[voxel] = glm::u8vec4(code);
        else wide_[voxel] = code;
    }
    glm::vec4 value(std::size_t voxel) const { return glm::vec4(code(voxel)) / code_max_; }
    bool transparent(std::size_t voxel) const { return code(voxel).a == 0; }
    // Every voxel decoded: a float volume for the reference compositor and for tests.
    ShadedVolume decoded() const;

private:
    glm::ivec3 dims_{0};
    glm::vec3 spacing_{1.0f};
    glm::vec4 code_max_{1.0f};  // per channel (r, g, b, opacity): the code that means 1
    bool narrow_storage_ = true;
    std::vector<glm::u8vec4> narrow_;
    std::vector<glm::u16vec4> wide_;
};

}  // namespace pp5
