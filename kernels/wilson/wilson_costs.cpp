#include "kernels/wilson/wilson_costs.h"

#include "kernels/shared/pp_volume/voxel_store_costs.h"
#include "kernels/shared/screen_regions/screen_region_costs.h"

namespace pp5 {

const ParamGroup& wilson_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.wilson",
                     "What each of Wilson's hybrid-rendering operations costs on an i860; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.hand_counted_flops(
            "texel_correction_flops", 20, "Correct one texel's opacity for the distance a ray travels between slices",
            "the path length (3), a logarithm and an exponential by table and polynomial (15), the store (2)");
        g.hand_counted_flops(
            "quad_parallel_flops", 100,
            "Make one cell's quad under a parallel camera: four bilinear channels as quadratics "
            "of the pixel position, and its screen box",
            "the corner differences (12), the texel map's substitution into four channels (4 x 15), the four corners' "
            "projections and the box (28)");
        g.hand_counted_flops(
            "quad_perspective_flops", 300,
            "Make one cell's quad under perspective: the second-order expansion of four "
            "channels about the cell centre's pixel, and its screen box",
            "nine ray-plane meetings (9 x 8), four channels at nine points (4 x 9 x 4), the differences (4 x 12), "
            "the shift to the origin (4 x 10), the corners and box (28)");
        g.hand_counted_flops("region_shift_flops", 40, "Move one quad's four quadratics to a further region's origin",
                             "4 x 10 multiply-adds");
        g.hand_counted_flops("slice_setup_flops", 30,
                             "Make one slice's setup expressions (the cell-index quadratics) for one region",
                             "three linear functions shifted to the region's origin and scaled");
        g.hand_counted_flops(
            "point_flops", 35, "Transform, classify, shade, correct and size one point",
            "the transform (9), the opacity and colour look-ups (4), the opacity correction (10), the normal's "
            "diffuse and "
            "specular terms from the frame's palette (2), the projected size and its rounding (6), the square's "
            "bounds (4)");
        g.hand_counted_flops("sheet_pixel_flops", 10, "Composite one point into one pixel of a GP's block (gp_sheets)",
                             "(1 - a) times four channels and four adds, a clamp");
        g.hand_counted_flops("quad_pixel_flops", 12, "Interpolate one pixel of a quad on a processor without PPs",
                             "four channels stepped incrementally (8), bounds and loop (4)");
        g.hand_counted_flops("composite_pixel_flops", 10, "Composite one pixel of a slice on a processor without PPs",
                             "(1 - a), seven multiplies and adds, the clear");
        g.hand_counted_flops("point_pixel_flops", 8, "Composite one pixel of a point on a processor without PPs",
                             "four multiply-adds");
        return g;
    }();
    return group;
}

std::vector<GpOpKind> wilson_op_kinds() {
    const auto key = [](const char* name) { return std::string("gp_cost.wilson.") + name; };
    // In WilsonOp's order.
    return {
        {"wilson.texel", {key("texel_correction_flops")}},
        {"wilson.quad_parallel", {key("quad_parallel_flops")}},
        {"wilson.quad_perspective", {key("quad_perspective_flops")}},
        {"wilson.region_shift", {key("region_shift_flops")}},
        {"wilson.coefficient", {kCoefficientConvertCost}},
        {"wilson.slice_setup", {key("slice_setup_flops")}},
        {"wilson.point", {key("point_flops")}},
        {"wilson.sheet_pixel", {key("sheet_pixel_flops")}},
        {"wilson.bin", {kBinCost}},
        {"wilson.pack_word", {kPackWordCost}},
        {"wilson.voxel_classification", {kVoxelClassificationCost}},
        {"wilson.voxel_shading", {kVoxelShadingCost}},
        {"wilson.quad_pixel", {key("quad_pixel_flops")}},
        {"wilson.composite_pixel", {key("composite_pixel_flops")}},
        {"wilson.point_pixel", {key("point_pixel_flops")}},
    };
}

}  // namespace pp5
