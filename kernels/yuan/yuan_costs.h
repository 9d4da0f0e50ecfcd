#pragma once
// The GP operations Yuan's kernel records and what each costs on an i860 ("gp_cost.yuan.*"): the GPs
// transform their bricks' voxels, split them into splats and points, set each splat's conic up (or
// filter each point into its band's sheet), bin them by screen region and pack the batches. The pixel
// operations are what a lone processor does instead of the renderers (a uniprocessor machine).

#include "sim/core/param.h"
#include "sim/timing/recorded_work.h"

#include <cstdint>
#include <vector>

namespace pp5 {

// Indices into yuan_op_kinds().
enum YuanOp : std::uint32_t {
    kYuanVoxel,                // transform a voxel, find its magnification and band, sort it into its chunk
    kYuanSplatSetup,           // the splat's cone, conic, bounding box and footprint row
    kYuanRegionShift,          // move a primitive's quadratics to another region's origin
    kYuanCoefficient,          // convert one coefficient to the QEE's fixed point
    kYuanPointSetup,           // a point's position, weights and paraboloid (renderer path)
    kYuanSheetPixel,           // filter a point into one pixel of the GP's sheet (gp_sheets path)
    kYuanBin,                  // place a primitive in one region's batch
    kYuanPackWord,             // pack one word of a batch
    kYuanVoxelClassification,  // on a processor without PPs
    kYuanVoxelShading,
    kYuanSplatPixel,      // a lone processor draws one pixel of a splat
    kYuanPointPixel,      // ... filters one point into one pixel
    kYuanCompositePixel,  // ... composites one pixel of a band's sheet
};

const ParamGroup& yuan_cost_params();
std::vector<GpOpKind> yuan_op_kinds();

}  // namespace pp5
