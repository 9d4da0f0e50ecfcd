#include "kernels/shared/screen_regions/screen_region_costs.h"

namespace pp5 {

const ParamGroup& screen_region_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.screen_regions",
                     "What sending screen-region primitives to the renderers costs a GP; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.real("coefficient_convert_cycles", 2, "cycles", 0, 1e7, "Convert one coefficient to the QEE's fixed point",
               Provenance::Default, "a scale and a float-to-integer")
            .hand_counted()
            .real("bin_cycles", 10, "cycles", 0, 1e7, "Place one primitive in one region's batch", Provenance::Default,
                  "a region look-up and a pointer bump")
            .hand_counted()
            .real("pack_cycles_per_word", 2, "cycles", 0, 1e7, "Pack one word of a batch for the ring",
                  Provenance::Default, "a store and a pointer bump")
            .hand_counted();
        return g;
    }();
    return group;
}

}  // namespace pp5
