// One GP phase: its agents, its groups, and when it is complete.
#include "sim/timing/engine_agents.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace pp5::engine {

namespace {

// The renderers' time answering fetches so far, summed.
}  // namespace

MachineCounters MachineCounters::of(Machine& machine) {
    MachineCounters c;
    for (const auto& gp : machine.gps()) {
        c.items += gp->items.value();
        c.fetch_requests += gp->fetch_requests.value();
        c.blocks_refreshed += gp->blocks_refreshed.value();
        c.context_switches += gp->context_switches.value();
        c.gp_busy += static_cast<Tick>(gp->busy_ps.value());
        c.gp_wait += static_cast<Tick>(gp->wait_ps.value());
        if (const BlockCache* cache = gp->cache_if_built()) {
            c.cache_hits += cache->hits.value();
            c.cache_misses += cache->misses.value();
        }
    }
    for (const auto& r : machine.renderers()) c.renderer_busy += static_cast<Tick>(r->fetch_busy_ps.value());
    c.ring_busy = static_cast<Tick>(machine.ring().busy_ps());
    c.events = machine.events().events_run();
    return c;
}

GpPhaseRun::GpPhaseRun(FrameRun& frame_in, Machine& machine_in, const GpPhase& phase_in,
                       const std::vector<GpOpKind>& kinds, PhaseTiming& timing_in)
    : frame(frame_in),
      machine(machine_in),
      phase(phase_in),
      timing(timing_in),
      op_cost(gp_op_costs(machine_in.config(), kinds)),
      host(*this) {
    for (const GpOpKind& k : kinds) op_names.push_back(k.name);
    if (machine.gps().size() >= (1u << 22)) throw std::invalid_argument("timing engine: too many GPs");
    remaining.resize(phase.tasks.size());
    open_tasks.assign(phase.groups, 0);
    for (std::size_t i = 0; i < phase.tasks.size(); ++i) {
        remaining[i] = phase.tasks[i].item_count;
        ++open_tasks.at(phase.tasks[i].group);
    }
    while (groups_done < open_tasks.size() && open_tasks[groups_done] == 0) ++groups_done;
    RingNetwork& ring = machine.ring();
    for (auto& gp : machine.gps())
        gps.push_back(
            std::make_unique<GpAgent>(*this, *gp, ring.position(StationKind::GraphicsProcessor, gp->index())));
    for (auto& r : machine.renderers())
        renderers.push_back(
            std::make_unique<RendererAgent>(*this, *r, ring.position(StationKind::Renderer, r->index())));
    frame_buffer = std::make_unique<FrameBufferAgent>(*this, machine.frame_buffer());
    frame_buffer_station = ring.position(StationKind::FrameBuffer, 0);
    host_station = ring.position(StationKind::Host, 0);
    pixel_bits = machine.frame_buffer().bits_per_pixel();
    for (auto& r : machine.renderers()) {
        std::vector<PpProgramCost> costs;
        for (const PpProgram& program : phase.region_programs) costs.push_back(r->cost_model().cost(program));
        region_costs.push_back(std::move(costs));
    }
    timing.gp.renderer_drawing.assign(machine.renderers().size(), 0);
    refresh_lists.resize(machine.gps().size());
    timing.task_gp.assign(phase.tasks.size(), std::numeric_limits<std::uint32_t>::max());
}

void GpPhaseRun::start(Tick t) {
    timing.start_ps = t;
    timing.end_ps = t;
    at_start = MachineCounters::of(machine);
    timing.group_end_ps.assign(phase.groups, t);  // a group that sends no pixels ends where the phase began
    if (phase.assignment == TaskAssignment::Static) {
        const std::size_t g = gps.size();
        for (std::uint32_t i = 0; i < phase.tasks.size(); ++i) gps[phase.tasks[i].key % g]->give_task(i);
    }
    for (auto& gp : gps) gp->begin(t);
    for (auto& r : renderers) r->begin(t);
}

void GpPhaseRun::readout_arrived(std::size_t, Tick now) {
    timing.end_ps = std::max(timing.end_ps, now);
    --pixel_messages_in_flight;
    maybe_complete(now);
}

void GpPhaseRun::items_done(std::uint32_t task, Tick t) {
    --open_tasks[phase.tasks[task].group];
    const std::uint32_t before = groups_done;
    while (groups_done < open_tasks.size() && open_tasks[groups_done] == 0) ++groups_done;
    if (groups_done != before)
        for (auto& gp : gps) gp->wake(t);
}

void GpPhaseRun::pixels_arrived(std::uint32_t task, Tick now) {
    Tick& end = timing.group_end_ps[phase.tasks[task].group];
    end = std::max(end, now);
    timing.end_ps = std::max(timing.end_ps, now);
    timing.gp.pixels_sent += phase.tasks[task].pixels;
    --pixel_messages_in_flight;
    maybe_complete(now);
}

void GpPhaseRun::maybe_complete(Tick now) {
    if (complete || gps_finished < gps.size() || regions_finished < renderers.size() || pixel_messages_in_flight > 0)
        return;
    complete = true;
    const MachineCounters at_end = MachineCounters::of(machine);
    GpPhaseCounts& g = timing.gp;
    g.items = at_end.items - at_start.items;
    g.cache_hits = at_end.cache_hits - at_start.cache_hits;
    g.cache_misses = at_end.cache_misses - at_start.cache_misses;
    g.fetch_requests = at_end.fetch_requests - at_start.fetch_requests;
    g.blocks_refreshed = at_end.blocks_refreshed - at_start.blocks_refreshed;
    g.context_switches = at_end.context_switches - at_start.context_switches;
    g.gp_busy = at_end.gp_busy - at_start.gp_busy;
    g.gp_wait = at_end.gp_wait - at_start.gp_wait;
    g.renderer_busy = at_end.renderer_busy - at_start.renderer_busy;
    g.ring_busy = at_end.ring_busy - at_start.ring_busy;
    g.events = at_end.events - at_start.events;
    // The phase ends when its last pixels reach the frame buffer (the picture is complete); a phase
    // that sends none ends when its GPs have finished.
    if (timing.gp.pixels_sent == 0 && !std::any_of(phase.regions.begin(), phase.regions.end(),
                                                   [](const RegionWork& r) { return r.readout_pixels > 0; }))
        timing.end_ps = now;
    frame.end_phase_at(std::max(now, timing.end_ps));
}

std::string GpPhaseRun::describe_stall() const {
    std::string why;
    for (const auto& gp : gps)
        if (!gp->finished()) why.append(1, ' ').append(gp->describe_stall());
    for (const auto& r : renderers) why += r->describe_stall();
    if (pixel_messages_in_flight > 0)
        why += fmt::format(" {} pixel message(s) on their way;", pixel_messages_in_flight);
    return why;
}

}  // namespace pp5::engine
