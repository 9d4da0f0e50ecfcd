#include "kernels/shared/screen_regions/screen_region_costs.h"

namespace pp5 {

const ParamGroup& screen_region_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.screen_regions",
                     "What sending screen-region primitives to the renderers costs a GP; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.hand_counted_cycles("coefficient_convert_cycles", 2, "Convert one coefficient to the QEE's fixed point",
                              "a scale and a float-to-integer");
        g.hand_counted_cycles("bin_cycles", 10, "Place one primitive in one region's batch",
                              "a region look-up and a pointer bump");
        g.hand_counted_cycles("pack_cycles_per_word", 2, "Pack one word of a batch for the ring",
                              "a store and a pointer bump");
        return g;
    }();
    return group;
}

}  // namespace pp5
