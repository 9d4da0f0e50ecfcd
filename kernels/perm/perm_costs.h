#pragma once
// The GP operations PERM's ray casting records and what each costs on an i860 ("gp_cost.perm.*"): a
// ray's setup, a sample that finds a candidate cell (the step, the mapping-table look-up, then
// classification, shading and compositing from the looked-up values, all on the GP as the paper
// does), a sample in a cell that is no candidate (the step and the index test), a sample the
// occupancy map lets the ray leap over, and a pixel sent to the frame buffer. With perm.shading = pp
// a sample instead reads the colour and opacity the PPs left at its density position (and depth-cues
// it when the lighting asks); a lone processor would classify and shade each record position itself.

#include "sim/core/param.h"
#include "sim/timing/recorded_work.h"

#include <cstdint>
#include <vector>

namespace pp5 {

enum PermOp : std::uint32_t {
    kPermRaySetup,
    kPermSample,
    kPermEmptySample,
    kPermLeapedSample,
    kPermPixel,
    kPermShadedSample,
    kPermDepthCue,
    kPermPositionClassification,
    kPermPositionShading,
};

const ParamGroup& perm_cost_params();
std::vector<GpOpKind> perm_op_kinds();

}  // namespace pp5
