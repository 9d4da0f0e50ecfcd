#pragma once
// Levoy's algorithms timed on one processor (a `uniprocessor` machine such as the Sun 4/280 he measured
// on): the same recorded work as on Pixel-planes 5 (levoy_renderer.h), done one step after another with
// the whole volume in memory. Each voxel is classified and shaded in turn, each polygon scan-converted
// voxel by voxel, the pyramid built, and every ray of every refinement pass cast, at the processor's
// per-operation costs (gp_cost.*). There are no messages, caches or waits: the time is a sum.

#include "kernels/levoy/levoy_renderer.h"
#include "sim/components/gp_cost_model.h"

#include <nlohmann/json_fwd.hpp>

#include <vector>

namespace pp5 {

struct SequentialFrameTiming {
    Tick classification = 0;
    Tick shading = 0;
    Tick region = 0;
    Tick scan_conversion = 0;
    Tick pyramid = 0;
    std::vector<Tick> pass_end;  // from the frame's start, after each refinement pass
    std::uint64_t polygons = 0;
    std::uint64_t polygon_voxels = 0;  // voxels the scan-converter visited

    Tick crude_ps() const { return pass_end.empty() ? before_ray_casting() : pass_end.front(); }
    Tick refined_ps() const { return pass_end.empty() ? before_ray_casting() : pass_end.back(); }
    Tick before_ray_casting() const { return classification + shading + region + scan_conversion + pyramid; }
    nlohmann::json to_json() const;
};

// A sequential scan-converter visits the voxels within one voxel of the polygon's plane over its area
// (about twice the area) and tests each of its J sample points against the plane and every edge.
inline constexpr double kSequentialVoxelsPerUnitArea = 2.0;

SequentialFrameTiming time_levoy_frame_sequentially(const GpCostModel& costs, const LevoyFrameWork& work);

}  // namespace pp5
