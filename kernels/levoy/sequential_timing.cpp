#include "kernels/levoy/sequential_timing.h"

#include "sim/core/time.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace pp5 {

SequentialFrameTiming time_levoy_frame_sequentially(const GpCostModel& costs, const LevoyFrameWork& work) {
    SequentialFrameTiming timing;
    const auto voxels = static_cast<Tick>(work.voxels);
    if (work.pixel_processors.classification) timing.classification = voxels * costs.voxel_classification;
    if (work.pixel_processors.shading) timing.shading = voxels * costs.voxel_shading;
    if (work.region) timing.region = voxels * costs.voxel_region;
    if (work.scan_converted) {
        timing.polygons = work.polygons;
        for (const PolygonWork& polygon : work.polygon_passes) {
            const auto visited = static_cast<std::uint64_t>(std::llround(kSequentialVoxelsPerUnitArea * polygon.area));
            const auto tests = static_cast<Tick>(work.jitter_samples) * static_cast<Tick>(polygon.edges + 1);
            timing.polygon_voxels += visited;
            timing.scan_conversion += static_cast<Tick>(visited) * (tests * costs.polygon_point_test + costs.voxel_matte);
        }
    }
    if (work.pyramid) timing.pyramid = static_cast<Tick>(work.pyramid->cells) * costs.pyramid_build_per_cell;

    // Every pass's rays, then its refinement decisions and interpolated pixels.
    const RayCastJob& job = work.ray_cast;
    std::vector<Tick> pass_work(job.passes.size(), 0);
    for (std::size_t p = 0; p < job.passes.size(); ++p) {
        for (const RayWork& ray : job.passes[p].rays) {
            pass_work[p] += costs.ray_setup + static_cast<Tick>(ray.samples) * costs.per_sample() +
                            static_cast<Tick>(ray.pyramid_steps) * costs.pyramid_step;
        }
    }
    for (const TileTask& task : job.tasks) {
        pass_work[static_cast<std::size_t>(task.pass)] +=
            static_cast<Tick>(task.squares_tested) * costs.refinement_test + static_cast<Tick>(task.pixels_filled) * costs.pixel_fill;
    }
    Tick t = timing.before_ray_casting();
    for (const Tick w : pass_work) timing.pass_end.push_back(t += w);
    return timing;
}

nlohmann::json SequentialFrameTiming::to_json() const {
    nlohmann::json passes = nlohmann::json::array();
    for (const Tick t : pass_end) passes.push_back(ticks_to_seconds(t));
    return {{"crude_seconds", ticks_to_seconds(crude_ps())},
            {"refined_seconds", ticks_to_seconds(refined_ps())},
            {"phases_seconds",
             {{"classification", ticks_to_seconds(classification)},
              {"shading", ticks_to_seconds(shading)},
              {"region_of_interest", ticks_to_seconds(region)},
              {"scan_conversion", ticks_to_seconds(scan_conversion)},
              {"pyramid", ticks_to_seconds(pyramid)}}},
            {"pass_end_seconds", passes},
            {"polygons", polygons},
            {"polygon_voxels_visited", polygon_voxels}};
}

}  // namespace pp5
