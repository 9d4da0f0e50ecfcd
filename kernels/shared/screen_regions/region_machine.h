#pragma once
// What a kernel that draws screen-region primitives needs of the machine and reports of it: the
// renderers' shape (a renderer's PP array is one 128x128 region of the screen) with where the voxel
// store keeps each voxel, and the sort-middle phase's account for stats.json.

#include "sim/machine/machine.h"
#include "sim/timing/frame_timing.h"

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include <functional>

namespace pp5 {

struct RegionMachine {
    int region_columns = 128;
    int region_rows = 128;
    int renderers = 16;
    int local_memory_bits = 208;
    std::function<int(glm::ivec3)> renderer_of_voxel;  // where the voxel store keeps each voxel

    // The renderers' shape from the configuration; the voxels' places come from the voxel store.
    static RegionMachine from(const Machine& machine, std::function<int(glm::ivec3)> renderer_of_voxel);
};

// A sort-middle GP phase's times and counts (GPs, ring, each renderer's drawing and their imbalance,
// the brick cache, batches).
nlohmann::json region_phase_stats(const GpPhaseCounts& counts);

}  // namespace pp5
