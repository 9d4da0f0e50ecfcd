#include "kernels/perm/perm_costs.h"

namespace pp5 {

const ParamGroup& perm_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.perm", "What each of PERM's ray-casting operations costs on an i860; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.hand_counted_flops("ray_setup_flops", 60,
                             "Set one ray up: its direction, where it enters the volume, its first sample",
                             "as Levoy's ray setup");
        g.hand_counted_flops("sample_step_flops", 6, "Step to the next sample",
                             "three adds and the loop test, as Levoy's");
        g.hand_counted_flops("lookup_flops", 6, "Find the sample's quantized position: the three fractions' QBM-ths",
                             "three subtractions of the floor and three multiplies");
        g.hand_counted_cycles("lookup_cycles", 8,
                              "Read the three mapping tables, combine the digits, read the index volume and the record",
                              "three table loads, two multiply-adds of the digits, the index load and the sign decode");
        g.hand_counted_flops("classification_flops", 8, "Classify the looked-up value and gradient magnitude",
                             "as Levoy's per-voxel classification");
        g.hand_counted_flops("shading_flops", 40, "Phong-shade the sample from the looked-up gradient",
                             "as Levoy's per-voxel shading");
        g.hand_counted_flops("compositing_flops", 10, "Composite the sample front to back", "as Levoy's");
        g.hand_counted_cycles("index_test_cycles", 4, "Find a sample's cell empty in the index volume",
                              "the cell's index, a load and a compare");
        g.hand_counted_cycles("leap_cycles_per_sample", 1,
                              "Leap one sample of empty space through the occupancy distance map",
                              "a distance-map read every few samples and the jump, spread over the samples leapt");
        g.hand_counted_flops("depth_cue_flops", 4,
                             "Depth-cue a PP-shaded sample: its depth along the view, then the colour over k1 + k2 d",
                             "a dot product's three multiply-adds and one divide (perm.shading = pp only)");
        g.hand_counted_flops("pixel_fill_flops", 18, "Pack one pixel for the frame buffer", "as Levoy's");
        return g;
    }();
    return group;
}

std::vector<GpOpKind> perm_op_kinds() {
    const auto key = [](const char* name) { return std::string("gp_cost.perm.") + name; };
    return {
        {"perm.ray_setup", {key("ray_setup_flops")}},
        {"perm.sample",
         {key("sample_step_flops"), key("lookup_flops"), key("lookup_cycles"), key("classification_flops"),
          key("shading_flops"), key("compositing_flops")}},
        {"perm.empty_sample", {key("sample_step_flops"), key("index_test_cycles")}},
        {"perm.leaped_sample", {key("leap_cycles_per_sample")}},
        {"perm.pixel", {key("pixel_fill_flops")}},
        {"perm.shaded_sample",
         {key("sample_step_flops"), key("lookup_flops"), key("lookup_cycles"), key("compositing_flops")}},
        {"perm.depth_cue", {key("depth_cue_flops")}},
        {"perm.position_classification", {key("classification_flops")}},
        {"perm.position_shading", {key("shading_flops")}},
    };
}

}  // namespace pp5
