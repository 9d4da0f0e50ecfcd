#pragma once
// Changing a volume's grid, e.g. to fit the simulated machine's 256^3 voxel memory.

#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

namespace pp5 {

// Trilinear resampling onto target_dims. The mapping is cell-centred: each voxel is a cell of the
// physical extent, and target voxel j samples the source at (j + 0.5) * n_src / n_dst - 0.5 (clamped
// to the grid), so the physical extent (dims * spacing) is unchanged and spacing scales by
// n_src / n_dst. Same dims give an exact copy. Point sampling without a prefilter: shrinking by more
// than 2x aliases fine detail. Deterministic. Source type and name are kept.
// Throws std::invalid_argument for an empty volume or a target dimension < 1.
Volume resample(const Volume& volume, glm::ivec3 target_dims);

}  // namespace pp5
