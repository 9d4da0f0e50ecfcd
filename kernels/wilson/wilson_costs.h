#pragma once
// The GP operations Wilson's kernel records and what each costs on an i860 ("gp_cost.wilson.*"): the
// GPs correct their bricks' texel opacities for the slice spacing, turn each non-transparent texel cell
// into a quad's quadratics, shade and size their points (or composite them into blocks), bin
// everything by screen region and pack the batches. The pixel operations are what a lone processor
// does instead of the renderers (a uniprocessor machine).

#include "sim/core/param.h"
#include "sim/timing/recorded_work.h"

#include <cstdint>
#include <vector>

namespace pp5 {

// Indices into wilson_op_kinds().
enum WilsonOp : std::uint32_t {
    kWilsonTexel,                // correct one texel's opacity for the distance between slices
    kWilsonQuadParallel,         // a cell's four bilinear channels as quadratics, and its screen box
    kWilsonQuadPerspective,      // ... their second-order expansions under perspective
    kWilsonRegionShift,          // move a quad's quadratics to a further region's origin
    kWilsonCoefficient,          // convert one coefficient to the QEE's fixed point
    kWilsonSliceSetup,           // one slice's setup expressions for one region
    kWilsonPoint,                // transform, classify, shade, correct and size one point
    kWilsonSheetPixel,           // composite one point into one pixel of a GP's block (gp_sheets)
    kWilsonBin,                  // place a primitive in one region's batch
    kWilsonPackWord,             // pack one word of a batch
    kWilsonVoxelClassification,  // on a processor without PPs
    kWilsonVoxelShading,
    kWilsonQuadPixel,       // a lone processor interpolates one pixel of a quad
    kWilsonCompositePixel,  // ... composites one pixel of a slice
    kWilsonPointPixel,      // ... composites one pixel of a point
};

const ParamGroup& wilson_cost_params();
std::vector<GpOpKind> wilson_op_kinds();

}  // namespace pp5
