#pragma once
// Stage 1 of Levoy's pipeline: the gradient of every voxel. It depends on the data alone, so it is
// computed once per volume and kept across changes of classification, shading and view.

#include "kernels/volume/volume.h"

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

}  // namespace pp5
