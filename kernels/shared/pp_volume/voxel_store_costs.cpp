#include "kernels/shared/pp_volume/voxel_store_costs.h"

namespace pp5 {

const ParamGroup& voxel_store_cost_params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.voxel_store",
                     "What classifying and shading one voxel costs a processor without PPs; none is published");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.hand_counted_flops("classification_flops", 8,
                             "Classify one voxel on a processor without PPs: opacity from value and gradient",
                             "a table look-up, the gradient magnitude's scale and a multiply: about 8");
        g.hand_counted_flops("shading_flops", 40, "Phong-shade one voxel on a processor without PPs",
                             "normalise the gradient (about 12 with a reciprocal square root), the diffuse dot "
                             "product and clamp (6), three colour multiply-adds with the ambient term (9), and the "
                             "opacity-weighted colour (4); with the look-ups, about 40");
        return g;
    }();
    return group;
}

}  // namespace pp5
