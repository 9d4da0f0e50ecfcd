#pragma once
// When a frame's recorded work (recorded_work.h) happened on one machine: the frame's span and each
// phase's, with what the timing engine counted along the way. Kernels read their metrics from here
// (crude and refined times, a phase's rate) whether the frame ran on Pixel-planes 5 or on one processor.

#include "sim/core/time.h"
#include "sim/pixel_processors/pp_cost_model.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pp5 {

// One PP program's pass over the renderers: the busiest renderer's time and one slot's cost.
struct PpPassTiming {
    Tick start_ps = 0;
    Tick end_ps = 0;
    std::uint64_t instructions = 0;  // in the program
    int local_memory_bits_used = 0;
    PpProgramCost slot_cost;  // one voxel slot
    PpPassCycles busiest;     // the renderer that finished last
    std::uint64_t slots = 0;  // on that renderer
};

// What the GPs did in a GpPhase, summed over GPs, channels or renderers.
struct GpPhaseCounts {
    std::uint64_t items = 0;
    std::uint64_t cache_hits = 0;
    std::uint64_t cache_misses = 0;
    std::uint64_t fetch_requests = 0;    // messages to renderers
    std::uint64_t blocks_refreshed = 0;  // asked for again in refresh messages (FrameWork::refresh_gp_caches)
    std::uint64_t context_switches = 0;
    std::uint64_t pixels_sent = 0;
    Tick gp_busy = 0;
    Tick gp_wait = 0;                // work left, nothing to run (fetches outstanding, or the next group not open)
    Tick renderer_busy = 0;          // answering fetches
    std::uint64_t batches_sent = 0;  // primitive batches and pixel blocks to renderers
    std::uint64_t batch_bits = 0;
    std::uint64_t primitives_drawn = 0;  // region program runs on the renderers
    std::vector<Tick> renderer_drawing;  // per renderer: time spent on its screen region (writes and draws)
    Tick ring_busy = 0;
    std::uint64_t events = 0;
};

struct PhaseTiming {
    std::string name;
    Tick start_ps = 0;
    Tick end_ps = 0;
    std::vector<PpPassTiming> passes;    // PpPhase
    std::vector<Tick> group_end_ps;      // GpPhase: when each group's last pixels reached the frame buffer
    GpPhaseCounts gp;                    // GpPhase
    std::vector<std::uint32_t> task_gp;  // GpPhase: the GP that ran each task
    Tick duration_ps() const { return end_ps - start_ps; }
};

// How busy each kind of component was over a frame: its busy time over the frame, from the components'
// own counters (read before and after it), as a share of the count times the frame's duration.
struct FrameActivity {
    double gps = 0.0;
    double renderers = 0.0;
    double ring = 0.0;  // over its channels
};

struct FrameTiming {
    Tick start_ps = 0;
    Tick end_ps = 0;
    std::vector<PhaseTiming> phases;
    FrameActivity activity;
    // The phase of that name, or nullptr.
    const PhaseTiming* phase(const std::string& name) const;
    Tick duration_ps() const { return end_ps - start_ps; }
};

}  // namespace pp5
