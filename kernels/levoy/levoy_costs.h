#pragma once
// The GP operations Levoy's kernel records (recorded_work.h), and what each costs on an i860
// ("gp_cost.levoy.*"). The ray caster's operations run on Pixel-planes 5's GPs; the voxel and polygon
// operations are what a lone processor does instead of the PPs (the Sun 4/280 of Levoy's measurements).

#include "sim/core/param.h"
#include "sim/timing/recorded_work.h"

#include <cstdint>
#include <vector>

namespace pp5 {

// Indices into levoy_op_kinds().
enum LevoyOp : std::uint32_t {
    kRaySetup,
    kSample,  // step to the next sample, interpolate, composite
    kPyramidStep,
    kRefinementTest,
    kPixelFill,
    kPyramidBuildCell,
    kVoxelClassification,
    kVoxelShading,
    kVoxelRegion,
    kPolygonPointTest,
    kVoxelMatte,
};

const ParamGroup& levoy_cost_params();
std::vector<GpOpKind> levoy_op_kinds();

}  // namespace pp5
