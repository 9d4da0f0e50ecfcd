#include "kernels/yuan/yuan_costs.h"

#include "kernels/shared/pp_volume/voxel_store_costs.h"
#include "kernels/shared/screen_regions/screen_region_costs.h"

namespace pp5 {

const ParamGroup& yuan_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.yuan", "What each of Yuan's splatting operations costs on an i860; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.hand_counted_flops("voxel_transform_flops", 18, "Transform one voxel's centre into eye space",
                             "a 3x3 matrix and a translation");
        g.hand_counted_flops("voxel_split_flops", 11,
                             "Find a voxel's magnification and depth band and decide splat or point",
                             "a reciprocal of depth, the projected spacing, the band's floor and a compare");
        g.hand_counted_cycles("voxel_sort_cycles", 20,
                              "Append a voxel to its (band, brick) chunk, in depth order within it",
                              "a bucket append and an insertion step on nearly sorted depths");
        g.hand_counted_flops(
            "splat_setup_flops", 80,
            "Set up one splat: cone angle, the six conic coefficients, centre, axes, bounding box, "
            "the footprint row and the colour constants",
            "|c|^2 and a reciprocal square root (12), the direction Q (4), cos^2 alpha (3), coefficients (14), the "
            "index normalisation at the centre (12), axes and box (25), colour and opacity (10)");
        g.hand_counted_flops("region_shift_flops", 10, "Move one primitive's quadratic to a further region's origin",
                             "the shift of F, D and E: about 10 multiply-adds");
        g.hand_counted_flops(
            "point_setup_flops", 16,
            "Set up one point for the renderers: its screen position, area and four paraboloid weights",
            "the projection (4), the area (1), four channel weights (4) and the paraboloid's terms (7)");
        g.hand_counted_flops("sheet_pixel_flops", 14, "Filter one point into one pixel of the GP's band sheet",
                             "the squared distance (4), the paraboloid weight (2), four multiply-adds");
        // Work Pixel-planes 5 gives its PPs, done by a lone processor (the `uniprocessor` machine kind;
        // classifying and shading a voxel cost what gp_cost.voxel_store.* says, whichever kernel asks).
        g.hand_counted_flops(
            "splat_pixel_flops", 20, "Draw one pixel of a splat on a processor without PPs",
            "the index quadratic stepped incrementally (3), the table look-up, alpha w (1), (1 - A) alpha (2), "
            "three colour multiply-adds and the opacity (8), bounds and loop (6)");
        g.hand_counted_flops("point_pixel_flops", 14, "Filter one point into one pixel on a processor without PPs",
                             "as sheet_pixel_flops");
        g.hand_counted_flops("composite_pixel_flops", 10,
                             "Composite one pixel of a band's sheet on a processor without PPs",
                             "(1 - A), a clamp, four multiply-adds and the clear");
        return g;
    }();
    return group;
}

std::vector<GpOpKind> yuan_op_kinds() {
    const auto key = [](const char* name) { return std::string("gp_cost.yuan.") + name; };
    // In YuanOp's order.
    return {
        {"yuan.voxel", {key("voxel_transform_flops"), key("voxel_split_flops"), key("voxel_sort_cycles")}},
        {"yuan.splat_setup", {key("splat_setup_flops")}},
        {"yuan.region_shift", {key("region_shift_flops")}},
        {"yuan.coefficient", {kCoefficientConvertCost}},
        {"yuan.point_setup", {key("point_setup_flops")}},
        {"yuan.sheet_pixel", {key("sheet_pixel_flops")}},
        {"yuan.bin", {kBinCost}},
        {"yuan.pack_word", {kPackWordCost}},
        {"yuan.voxel_classification", {kVoxelClassificationCost}},
        {"yuan.voxel_shading", {kVoxelShadingCost}},
        {"yuan.splat_pixel", {key("splat_pixel_flops")}},
        {"yuan.point_pixel", {key("point_pixel_flops")}},
        {"yuan.composite_pixel", {key("composite_pixel_flops")}},
    };
}

}  // namespace pp5
