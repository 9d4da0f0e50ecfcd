#include "kernels/levoy/levoy_costs.h"

#include "kernels/shared/pp_volume/voxel_store_costs.h"

namespace pp5 {

const ParamGroup& levoy_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.levoy", "What each of Levoy's GP operations costs on an i860; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.hand_counted_flops("ray_setup_flops", 60,
                             "Set up a ray: origin, direction, entry into and exit from the volume",
                             "a pixel's ray (about 15 flops) and a slab test against the box (about 45)");
        g.hand_counted_flops("sample_step_flops", 6, "Advance a ray to its next sample and find the cell around it",
                             "three adds for the position, three conversions for the cell");
        g.hand_counted_flops("interpolation_flops", 56, "Trilinear interpolation of colour and opacity at a sample",
                             "seven linear interpolations (two flops each) in four channels");
        g.hand_counted_flops("compositing_flops", 10, "Composite one sample front to back and test for termination",
                             "(1 - A) alpha, three colour multiply-adds, the opacity update and a compare");
        g.hand_counted_flops("pixel_fill_flops", 18,
                             "Fill a pixel that was not cast by interpolating its square's corners",
                             "bilinear interpolation: three linear interpolations in three channels");
        g.hand_counted_flops(
            "refinement_test_flops", 24, "Decide whether to subdivide a square from its corner colours",
            "six corner pairs in three channels: a subtract and a compare each is 36; with early exit about 24");
        // Work that Pixel-planes 5 gives its PPs, done by a lone processor (the `uniprocessor` machine kind;
        // classifying and shading a voxel cost what gp_cost.voxel_store.* says, whichever kernel asks).
        g.hand_counted_flops("voxel_region_flops", 12,
                             "Scale one voxel's opacity by the volume-of-interest tool on a processor without PPs",
                             "the distance to a box or ellipsoid (about 9) and the scale across the transition (3)");
        g.hand_counted_flops(
            "polygon_point_test_flops", 2,
            "Test one subvoxel sample point against one of a polygon's planes (sheet or edge)",
            "the plane's linear function stepped incrementally along a scanline (an add) and a compare");
        g.hand_counted_flops("voxel_matte_flops", 12, "Matte a scan-converted polygon over one voxel",
                             "coverage times opacity, the opacity update and three colour blends");
        g.hand_counted_cycles(
            "pyramid_step_cycles", 40, "Visit one cell of the pyramid of binary volumes",
            "a bit test, a level change or a box exit: about 20 flops of bookkeeping at 2 cycles each");
        g.hand_counted_cycles("pyramid_build_cycles_per_cell", 2,
                              "Build one cell of the pyramid of binary volumes from the bits below it",
                              "an OR of eight bits, done a word of cells at a time");
        return g;
    }();
    return group;
}

std::vector<GpOpKind> levoy_op_kinds() {
    const auto key = [](const char* name) { return std::string("gp_cost.levoy.") + name; };
    // In LevoyOp's order.
    return {
        {"levoy.ray_setup", {key("ray_setup_flops")}},
        {"levoy.sample", {key("sample_step_flops"), key("interpolation_flops"), key("compositing_flops")}},
        {"levoy.pyramid_step", {key("pyramid_step_cycles")}},
        {"levoy.refinement_test", {key("refinement_test_flops")}},
        {"levoy.pixel_fill", {key("pixel_fill_flops")}},
        {"levoy.pyramid_build_cell", {key("pyramid_build_cycles_per_cell")}},
        {"levoy.voxel_classification", {kVoxelClassificationCost}},
        {"levoy.voxel_shading", {kVoxelShadingCost}},
        {"levoy.voxel_region", {key("voxel_region_flops")}},
        {"levoy.polygon_point_test", {key("polygon_point_test_flops")}},
        {"levoy.voxel_matte", {key("voxel_matte_flops")}},
    };
}

}  // namespace pp5
