#pragma once
// What a processor without PPs pays for the voxel store's work ("gp_cost.voxel_store.*"): on a
// uniprocessor machine every kernel whose PPs hold the volume classifies and shades it voxel by voxel
// instead, at the same cost whichever kernel asks.

#include "sim/core/param.h"

namespace pp5 {

const ParamGroup& voxel_store_cost_params();

inline constexpr const char* kVoxelClassificationCost = "gp_cost.voxel_store.classification_flops";
inline constexpr const char* kVoxelShadingCost = "gp_cost.voxel_store.shading_flops";

}  // namespace pp5
