#pragma once
// Levoy's kernel's own parameters ("levoy.*"): how the GPs cast rays over the voxels the pixel
// processors hold ("voxel_store.*", kernels/shared/pp_volume/pp_shading.h), and how polygons are scan-converted.

#include "kernels/levoy/adaptive_refinement.h"
#include "kernels/shared/pp_volume/pp_shading.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"
#include "sim/core/param.h"
#include "sim/timing/recorded_work.h"

namespace pp5 {

struct LevoySettings {
    VoxelStoreSettings store;
    int block_cells = 4;
    TaskAssignment ray_assignment = TaskAssignment::Static;  // tiles dealt round-robin, or from the host's queue
    bool interleave_tiles = true;  // static: skew each row of tiles so one GP's tiles spread in both directions
    int tile_pixels = 16;
    RefinementSettings refinement;
    bool pyramid_skipping = true;
    bool depth_buffer = true;
    bool refresh_caches = false;  // after a reshade, GPs ask again for the blocks they used (false: they drop them)
    int refresh_blocks_per_message = 16;
    int jitter_samples = 16;
    double scan_voxels_per_area = 2.0;  // a sequential scan-converter's voxels visited per unit area (one processor)
    // Bits a voxel's record keeps for the stationary lights' precomputed sum (0: recompute them at every
    // reshade). for_scenario() adds the field to the layout only when some frame has stationary lights.
    int stationary_light_bits = 10;

    static const ParamGroup& params();
    static LevoySettings from(const MachineConfig& config);
    // The same, with the record's stationary-light field when a frame of `scenario` has stationary lights.
    static LevoySettings for_scenario(const MachineConfig& config, const Scenario& scenario);
};

}  // namespace pp5
