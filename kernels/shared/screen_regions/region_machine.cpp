#include "kernels/shared/screen_regions/region_machine.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

namespace pp5 {

RegionMachine RegionMachine::from(const Machine& machine, std::function<int(glm::ivec3)> renderer_of_voxel) {
    const MachineShape& shape = machine.shape();
    RegionMachine m;
    m.region_columns = shape.pp_columns;
    m.region_rows = shape.pp_rows;
    m.renderers = shape.renderers;
    m.local_memory_bits = shape.local_memory_bits;
    m.renderer_of_voxel = std::move(renderer_of_voxel);
    return m;
}

nlohmann::json region_phase_stats(const GpPhaseCounts& g) {
    const auto seconds = [](Tick t) { return ticks_to_seconds(t); };
    std::vector<double> drawing;
    for (const Tick t : g.renderer_drawing) drawing.push_back(seconds(t));
    const double busiest = drawing.empty() ? 0.0 : *std::max_element(drawing.begin(), drawing.end());
    const double mean =
        drawing.empty() ? 0.0
                        : std::accumulate(drawing.begin(), drawing.end(), 0.0) / static_cast<double>(drawing.size());
    return {{"gp_computing_seconds", seconds(g.gp_busy)},
            {"gp_waiting_seconds", seconds(g.gp_wait)},
            {"ring_busy_seconds", seconds(g.ring_busy)},
            {"renderers_answering_seconds", seconds(g.renderer_busy)},
            {"renderer_drawing_seconds", drawing},
            {"renderer_imbalance", mean > 0 ? busiest / mean : 0.0},
            {"note",
             "GP and ring times are summed over GPs and channels; imbalance is the busiest renderer's drawing time "
             "over the mean"},
            {"fetch_requests", g.fetch_requests},  // a brick of the volume each
            {"cache_hits", g.cache_hits},
            {"cache_misses", g.cache_misses},
            {"batches_sent", g.batches_sent},
            {"batch_bits", g.batch_bits},
            {"primitives_drawn", g.primitives_drawn},
            {"events", g.events}};
}

}  // namespace pp5
