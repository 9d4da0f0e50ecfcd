#pragma once
// Stage 1 of Levoy's pipeline: the gradient of every voxel. It depends on the data alone, so it is
// computed once per volume and kept across changes of classification, shading and view.

#include "scene/volume/volume.h"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace pp5 {

struct GradientField {
    glm::ivec3 dims{0};
    std::vector<glm::vec3> gradients;  // value units per voxel, per voxel, in Volume::index order

    const glm::vec3& at(std::size_t index) const { return gradients[index]; }
};

// Central differences in voxel units, g_x = (f(x+1) - f(x-1)) / 2, with coordinates clamped to the grid
// at the borders (so a border voxel gets half its one-sided difference). Slices run in parallel.
GradientField compute_gradients(const Volume& volume);

// One voxel's gradient, with the same arithmetic: for a reader that needs each gradient once (loading
// the PPs) and so need not hold the field's 12 bytes a voxel.
inline glm::vec3 central_difference(const Volume& volume, glm::ivec3 v) {
    const glm::ivec3 last = volume.dims() - 1;
    const auto at = [&](int x, int y, int z) { return volume.samples()[volume.index(x, y, z)]; };
    const glm::ivec3 lo = glm::max(v - 1, glm::ivec3(0));
    const glm::ivec3 hi = glm::min(v + 1, last);
    return 0.5f * glm::vec3(at(hi.x, v.y, v.z) - at(lo.x, v.y, v.z), at(v.x, hi.y, v.z) - at(v.x, lo.y, v.z),
                            at(v.x, v.y, hi.z) - at(v.x, v.y, lo.z));
}

// The largest magnitude of any component of any voxel's gradient, without keeping the field.
float largest_gradient_component(const Volume& volume);

}  // namespace pp5
