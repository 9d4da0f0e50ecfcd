#include "scene/reference/reference_costs.h"

namespace pp5 {

const ParamGroup& reference_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.reference", "What the reference renderer's ray-casting loop costs on a processor");
        g.all_timing_only();  // it changes when work happens, never what is computed
        const char* same = "the operation count of the same work in Levoy's ray caster (gp_cost.levoy)";
        g.hand_counted_flops("ray_setup_flops", 60,
                             "Set up a ray: origin, direction, entry into and exit from the volume", same);
        g.hand_counted_flops("sample_step_flops", 6, "Advance a ray to its next sample", same);
        g.hand_counted_flops("interpolation_flops", 56, "Trilinear interpolation at a sample", same);
        g.hand_counted_flops("compositing_flops", 10, "Composite a sample front to back", same);
        return g;
    }();
    return group;
}

std::vector<std::string> reference_ray_setup_cost_keys() { return {"gp_cost.reference.ray_setup_flops"}; }

std::vector<std::string> reference_sample_cost_keys() {
    return {"gp_cost.reference.sample_step_flops", "gp_cost.reference.interpolation_flops",
            "gp_cost.reference.compositing_flops"};
}

}  // namespace pp5
