#include "kernels/levoy/levoy_settings.h"

namespace pp5 {

const ParamGroup& LevoySettings::params() {
    static const ParamGroup group = [] {
        ParamGroup g("levoy",
                     "Levoy's volume rendering kernel: the GPs' ray casting over the voxels the pixel processors hold");
        g.integer("block_cells", 4, "cells", 1, 64,
                  "Cells along each edge of the block one voxel request asks for ((n+1)^3 voxels)", Provenance::Default,
                  "Levoy 1989: GPs 'request sets of voxels', size not given")
            .text("ray_assignment", "interleaved_tiles", {"interleaved_tiles", "static_tiles", "work_queue"},
                  "Which GP casts which rays: tiles dealt round-robin with each row of tiles skewed so that every GP's "
                  "tiles spread over the whole picture (interleaved_tiles), dealt round-robin in raster order "
                  "(static_tiles: with as many GPs as tiles in a row, each GP gets one column), or handed out by the "
                  "host "
                  "as GPs ask",
                  Provenance::Default, "Levoy 1989: 'each is assigned a set of rays', policy not given")
            .integer("tile_pixels", 16, "pixels", 1, 4096, "Edge of the square tiles of rays a GP works on",
                     Provenance::Default, "pp5sim")
            .integer("refinement_spacing", 8, "pixels", 1, 1024, "Pixels between the rays of the first, sparse pass",
                     Provenance::Paper, "Levoy 1990 (adaptive refinement): one ray per 4x4 or 8x8 pixels first")
            .real("refinement_threshold", 0.1, "colour", -1, 1,
                  "A square splits when its corners differ by more than this in r, g or b (0-1); below 0 every pixel "
                  "is cast",
                  Provenance::Default, "Levoy 1990 uses a colour-difference threshold; its value is ours")
            .boolean("pyramid_skipping", true, "Skip empty space with the pyramid of binary volumes", Provenance::Paper,
                     "Levoy 1989 and 1990: hierarchical spatial enumeration")
            .boolean(
                "depth_buffer", true,
                "While the observer and the set of non-empty voxels stay, start rays at the first non-empty sample "
                "found in an earlier frame. The depth is the one the pyramid's skipping finds, so without "
                "pyramid_skipping it has nothing to record and is reported off",
                Provenance::Paper, "Levoy 1989: record the depth of the first non-empty voxel along each ray")
            .text("after_reshade", "drop", {"drop", "refresh"},
                  "What the GPs do with their cached voxels when the PPs recompute colours or opacities: drop them and "
                  "fetch "
                  "each block again when a ray misses it (drop), or ask again at once for the blocks they used in the "
                  "frame "
                  "before, in the order they first used them, a few blocks a message (refresh: far fewer requests, but "
                  "every "
                  "GP takes in all of it while its crude pass runs)",
                  Provenance::Default,
                  "Levoy 1989: voxels a GP receives are kept in its cache for later frames; what a reshade does to "
                  "them is ours")
            .integer(
                "refresh_blocks_per_message", 16, "blocks", 1, 65536,
                "With after_reshade = refresh: blocks one refresh message asks a renderer for (renderers answer in the "
                "order requests come, so smaller messages bring every GP's first blocks back sooner)",
                Provenance::Default, "pp5sim")
            .real("scan_voxels_per_area", 2.0, "voxels", 1.0, 8.0,
                  "On one processor (the Sun 4/280), voxels a sequential 3D scan-converter visits per unit of a "
                  "polygon's "
                  "area inside the volume, testing each against the plane and every edge at every jitter sample",
                  Provenance::Default,
                  "pp5sim: the voxels within one voxel of the polygon's plane, a slab two voxels thick; Levoy 1989 "
                  "says only that "
                  "his Sun took time 'in proportion to its area'")
            .integer("jitter_samples", 16, "count", 1, 1024,
                     "Subvoxel translations of each polygon in 3D scan-conversion (1: binary voxelisation)",
                     Provenance::Default,
                     "Levoy 1989: 'moved through a set of subvoxel-sized translations', count not given")
            .integer(
                "stationary_light_bits", 10, "bits", 0, 16,
                "Bits each voxel's record keeps for the summed light of the scenario's stationary lights, stored by "
                "their own PP pass when they change and added by every reshade after (0: every reshade recomputes "
                "every "
                "light). The sum is in 1/256ths of a full light and saturates at 2^bits - 1 (10 bits: about 4 lights "
                "at "
                "full strength). Used only by scenarios with stationary lights",
                Provenance::Default,
                "Levoy 1989: with several lights of which one moves, 'the contribution made by the stationary sources "
                "can "
                "be pre-computed'; the field's width is ours");
        return g;
    }();
    return group;
}

LevoySettings LevoySettings::from(const MachineConfig& config) {
    LevoySettings s;
    s.store = VoxelStoreSettings::from(config);
    s.block_cells = static_cast<int>(config.integer("levoy.block_cells"));
    const std::string assignment = config.text("levoy.ray_assignment");
    s.ray_assignment = assignment == "work_queue" ? TaskAssignment::WorkQueue : TaskAssignment::Static;
    s.interleave_tiles = assignment == "interleaved_tiles";
    s.tile_pixels = static_cast<int>(config.integer("levoy.tile_pixels"));
    s.refinement.initial_spacing = static_cast<int>(config.integer("levoy.refinement_spacing"));
    s.refinement.threshold = static_cast<float>(config.real("levoy.refinement_threshold"));
    s.pyramid_skipping = config.boolean("levoy.pyramid_skipping");
    s.depth_buffer = config.boolean("levoy.depth_buffer");
    s.jitter_samples = static_cast<int>(config.integer("levoy.jitter_samples"));
    s.scan_voxels_per_area = config.real("levoy.scan_voxels_per_area");
    s.refresh_caches = config.text("levoy.after_reshade") == "refresh";
    s.refresh_blocks_per_message = static_cast<int>(config.integer("levoy.refresh_blocks_per_message"));
    s.stationary_light_bits = static_cast<int>(config.integer("levoy.stationary_light_bits"));
    return s;
}

LevoySettings LevoySettings::for_scenario(const MachineConfig& config, const Scenario& scenario) {
    LevoySettings s = from(config);
    if (has_stationary_lights(scenario)) s.store.layout.stationary_light_bits = s.stationary_light_bits;
    return s;
}

}  // namespace pp5
