#pragma once
// Whether this computer can hold a volume: every loader, phantom and resampling asks before it
// allocates, so a header or a scenario that declares more than memory allows is refused up front,
// saying how much it would need, instead of allocating until the system kills the run.

#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <string>

namespace pp5 {

// Throws InputError(file, field, ...) when holding a volume of `dims` (its source bytes while reading,
// then four bytes a voxel) would take more than half of this computer's memory (sim/core/host_memory.h).
void check_volume_fits_host(const std::string& file, const std::string& field, glm::ivec3 dims, ScalarType type);

}  // namespace pp5
