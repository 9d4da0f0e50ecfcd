#pragma once
// What the GPs pay to send screen-region primitives to the renderers ("gp_cost.screen_regions.*"),
// the same for every kernel that draws them: each coefficient converted to the QEE's fixed point,
// each primitive placed in its region's batch, each batch word packed for the ring.

#include "sim/core/param.h"

namespace pp5 {

const ParamGroup& screen_region_cost_params();

inline constexpr const char* kCoefficientConvertCost = "gp_cost.screen_regions.coefficient_convert_cycles";
inline constexpr const char* kBinCost = "gp_cost.screen_regions.bin_cycles";
inline constexpr const char* kPackWordCost = "gp_cost.screen_regions.pack_cycles_per_word";

}  // namespace pp5
