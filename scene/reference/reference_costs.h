#pragma once
// What the reference renderer's ray-casting loop costs on a processor, in the machine's cost model
// ("gp_cost.reference.*", flops at the processor's rate): a ray's setup, and a sample's step,
// trilinear interpolation and compositing. The defaults are the operation counts Levoy's ray caster
// uses for the same work (gp_cost.levoy.*); `pp5sim host-check` fits the host preset's scales with them.

#include "sim/core/param.h"

#include <string>
#include <vector>

namespace pp5 {

const ParamGroup& reference_cost_params();
// The cost parameters whose sum is one ray's setup, and one sample's work.
std::vector<std::string> reference_ray_setup_cost_keys();
std::vector<std::string> reference_sample_cost_keys();

}  // namespace pp5
