#include "sim/timing/frame_engine.h"

#include "sim/core/input_error.h"
#include "sim/timing/engine_agents.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <stdexcept>

namespace pp5 {

std::string to_string(TaskAssignment assignment) {
    return assignment == TaskAssignment::Static ? "static" : "work_queue";
}

BlockDirectory::BlockDirectory(std::uint64_t block_bits, std::uint32_t unit_bits, std::vector<std::uint32_t> first_part,
                               std::vector<BlockPart> parts)
    : block_bits_(block_bits), unit_bits_(unit_bits), first_part_(std::move(first_part)), parts_(std::move(parts)) {
    if (block_bits_ == 0 || unit_bits_ == 0 || first_part_.empty() || first_part_.back() != parts_.size())
        throw std::invalid_argument("block directory: inconsistent sizes");
}

void append_ops(std::vector<GpOp>& ops, std::uint32_t kind, std::uint64_t count) {
    constexpr std::uint64_t kMost = std::numeric_limits<std::uint32_t>::max();
    for (; count > 0; count -= std::min(count, kMost))
        ops.push_back(GpOp{kind, static_cast<std::uint32_t>(std::min(count, kMost))});
}

const PhaseTiming* FrameTiming::phase(const std::string& name) const {
    for (const PhaseTiming& p : phases)
        if (p.name == name) return &p;
    return nullptr;
}

std::vector<Tick> gp_op_costs(const MachineConfig& config, const std::vector<GpOpKind>& kinds) {
    std::vector<Tick> costs;
    for (const GpOpKind& kind : kinds) {
        Tick sum = 0;
        for (const std::string& key : kind.cost_keys) sum += GpCostModel::cost_of(config, key);
        costs.push_back(sum);
    }
    return costs;
}

namespace engine {

void FrameRun::check_machine_fits() const {
    check_picture_fits(machine_, work_.image_width, work_.image_height);
    const bool with_cache = std::any_of(work_.phases.begin(), work_.phases.end(), [](const Phase& p) {
        const auto* gp = std::get_if<GpPhase>(&p.work);
        return gp != nullptr && gp->blocks;
    });
    check_gp_memory_fits(machine_, with_cache, work_.gp_resident_bits, work_.resident_bits_by_key);
}

// Recorded work is a kernel's output: an index out of range is the kernel's bug, said before it runs.
void check_recorded_work(const FrameWork& work, const Machine& machine) {
    const auto fail = [](const std::string& phase, const std::string& what) {
        throw std::logic_error("recorded work, phase '" + phase + "': " + what);
    };
    const auto check_ops = [&](const std::string& phase, const std::vector<GpOp>& ops, std::uint64_t first,
                               std::uint64_t count) {
        if (first + count > ops.size()) fail(phase, "operations out of range");
        for (std::uint64_t i = first; i < first + count; ++i)
            if (ops[i].kind >= work.op_kinds.size()) fail(phase, "an operation of an undeclared kind");
    };
    for (const Phase& phase : work.phases) {
        if (const auto* pp = std::get_if<PpPhase>(&phase.work)) {
            for (const PpPhase::Pass& pass : pp->passes) {
                if (pass.work.slots.size() != machine.renderers().size() ||
                    pass.work.counts.size() != machine.renderers().size())
                    fail(phase.name, "a pass recorded for another renderer count");
                check_ops(phase.name, pass.on_one_processor, 0, pass.on_one_processor.size());
            }
        } else if (const auto* broadcast = std::get_if<BroadcastPhase>(&phase.work)) {
            if (broadcast->messages_per_renderer.size() != machine.renderers().size())
                fail(phase.name, "messages for another renderer count");
            check_ops(phase.name, broadcast->then_each_gp, 0, broadcast->then_each_gp.size());
        } else {
            const GpPhase& gp = std::get<GpPhase>(phase.work);
            for (const GpTask& task : gp.tasks) {
                if (task.group >= gp.groups) fail(phase.name, "a task in no group");
                if (std::uint64_t{task.first_item} + task.item_count > gp.items.size())
                    fail(phase.name, "items out of range");
                check_ops(phase.name, gp.ops, task.first_op, task.op_count);
                check_ops(phase.name, gp.ops, task.first_finish_op, task.finish_op_count);
            }
            for (const GpItem& item : gp.items)
                if (std::uint64_t{item.first_step} + item.step_count > gp.steps.size())
                    fail(phase.name, "steps out of range");
            for (const GpTask& task : gp.tasks)
                if (std::uint64_t{task.first_batch} + task.batch_count > gp.batches.size())
                    fail(phase.name, "batches out of range");
            check_ops(phase.name, gp.regions_on_one_processor, 0, gp.regions_on_one_processor.size());
            if (!gp.regions.empty() && gp.regions.size() != machine.renderers().size())
                fail(phase.name, "regions for another renderer count");
            for (const PrimitiveBatch& batch : gp.batches)
                if (batch.renderer >= gp.regions.size() || gp.regions[batch.renderer].steps.empty())
                    fail(phase.name, "a batch for a renderer with no region steps");
            for (std::size_t r = 0; r < gp.regions.size(); ++r) {
                for (const RegionStep& step : gp.regions[r].steps) {
                    if (step.program >= gp.region_programs.size())
                        fail(phase.name, "a region step of an unknown program");
                    if (step.batch != kNoBatch &&
                        (step.batch >= gp.batches.size() || gp.batches[step.batch].renderer != r))
                        fail(phase.name, "a region step drawing another renderer's batch");
                }
            }
            for (const GpStep& step : gp.steps) {
                check_ops(phase.name, gp.ops, step.first_op, step.op_count);
                if (step.block == kNoFetch) continue;
                if (!gp.blocks) fail(phase.name, "a fetch without a block directory");
                if (step.block >= gp.blocks->block_count()) fail(phase.name, "a fetch of a block the directory lacks");
            }
        }
    }
}

FrameTiming FrameRun::run(const EngineOptions& options) {
    check_recorded_work(work_, machine_);
    check_machine_fits();
    for (const Phase& p : work_.phases)
        if (const auto* gp = std::get_if<GpPhase>(&p.work); gp != nullptr && gp->blocks)
            for (auto& g : machine_.gps()) g->cache(gp->blocks->block_bits());  // InputError if a block does not fit
    for (auto& g : machine_.gps()) {
        BlockCache* cache = g->cache_if_built();
        if (cache == nullptr) continue;
        if (work_.refresh_gp_caches) {
            refresh_.resize(machine_.gps().size());
            refresh_[g->index()] = cache->blocks_used_this_frame();
        }
        if (work_.invalidate_gp_caches || work_.refresh_gp_caches) cache->invalidate();
        cache->begin_frame();
    }

    EventQueue& events = machine_.events();
    timing_.start_ps = events.now();
    timing_.end_ps = timing_.start_ps;
    timing_.phases.resize(work_.phases.size());
    for (std::size_t i = 0; i < work_.phases.size(); ++i) timing_.phases[i].name = work_.phases[i].name;
    try {
        if (!work_.phases.empty()) start_phase(0, timing_.start_ps);
        events.run_until(timing_.start_ps + options.watchdog_limit);
    } catch (...) {
        events.clear();  // the agents handling them are about to go
        throw;
    }

    if (current_ < work_.phases.size()) {
        const bool timed_out = !events.empty();
        std::string why = fmt::format(" phase '{}' did not finish;", work_.phases[current_].name);
        if (gp_run_) why += gp_run_->describe_stall();
        events.clear();  // the agents handling them are about to go
        throw std::runtime_error(
            fmt::format("watchdog: {} at {:.6f} s simulated:{}",
                        timed_out ? "the frame ran past the watchdog limit" : "the machine stalled with work left",
                        ticks_to_seconds(events.now()), why));
    }
    return std::move(timing_);
}

void FrameRun::handle_event(Tick now, std::uint64_t) {
    timing_.end_ps = std::max(timing_.end_ps, timing_.phases[current_].end_ps);
    ++current_;
    if (current_ < work_.phases.size()) start_phase(current_, now);
}

void FrameRun::start_phase(std::size_t index, Tick t) {
    const Phase& phase = work_.phases[index];
    PhaseTiming& timing = timing_.phases[index];
    timing.start_ps = t;
    timing.end_ps = t;
    if (const auto* pp = std::get_if<PpPhase>(&phase.work)) return start_pp_phase(*pp, timing, t);
    if (const auto* broadcast = std::get_if<BroadcastPhase>(&phase.work))
        return start_broadcast_phase(*broadcast, timing, t);
    gp_run_ = std::make_unique<GpPhaseRun>(*this, machine_, std::get<GpPhase>(phase.work), work_.op_kinds, timing);
    if (gp_run_->phase.blocks) {  // the frame's first phase that fetches asks again
        gp_run_->refresh = std::move(refresh_);
        gp_run_->refresh_blocks_per_message = work_.refresh_blocks_per_message;
        refresh_.clear();
    }
    gp_run_->start(t);
    gp_run_->maybe_complete(t);  // a phase without tasks ends at once
}

// Each renderer runs the passes in order on its own clock, each once its command (if any) has arrived.
void FrameRun::start_pp_phase(const PpPhase& phase, PhaseTiming& timing, Tick t) {
    auto& renderers = machine_.renderers();
    RingNetwork& ring = machine_.ring();
    EventQueue& events = machine_.events();
    for (const PpPhase::Pass& pass : phase.passes) {
        const PpPassWork& work = pass.work;
        if (renderers.size() != work.slots.size())
            throw std::logic_error("PP pass recorded for another renderer count");
        Tick start = t;
        if (pass.command_bits > 0)
            start = ring.transmit(t, RingMessage{MessageKind::Command, ring.position(StationKind::Host, 0), 0,
                                                 pass.command_bits, true})
                        .arrival;
        PpPassTiming p;
        p.start_ps = start;
        p.end_ps = start;
        const PpProgram& program = *work.program;
        p.instructions = program.instructions.size();
        p.local_memory_bits_used = program.local_memory_bits_used;
        for (std::size_t r = 0; r < renderers.size(); ++r) {
            Renderer& renderer = *renderers[r];
            const RendererPass run{program.name, renderer.cost_model().cost(program), work.slots[r], work.counts[r],
                                   program.local_memory_bits_used};
            const Tick end = renderer.begin_pass(events, start, run);
            if (end > p.end_ps || r == 0) {
                p.end_ps = end;
                p.slot_cost = run.cost;
                p.busiest = renderer.cost_model().pass(run.cost, run.slots);
                p.slots = run.slots;
            }
        }
        timing.passes.push_back(p);
    }
    for (const auto& r : renderers) timing.end_ps = std::max(timing.end_ps, r->busy_until());
    end_phase_at(timing.end_ps);
}

// Every renderer reads each message out of its PPs once they are free and broadcasts it; every GP takes
// each in after the one before (taking a message in is slower than the ring delivers it), then computes.
void FrameRun::start_broadcast_phase(const BroadcastPhase& phase, PhaseTiming& timing, Tick t) {
    RingNetwork& ring = machine_.ring();
    std::vector<std::pair<Tick, std::size_t>> ready;
    for (auto& r : machine_.renderers()) ready.emplace_back(std::max(t, r->busy_until()), r->index());
    std::sort(ready.begin(), ready.end());
    const std::uint64_t words_per_message = (phase.bits_per_message + 31) / 32;
    // Each renderer reads its messages out one after another; the ring takes them in time order.
    std::vector<std::pair<Tick, std::size_t>> read;  // (when a message can leave, its station)
    for (const auto& [at, r] : ready) {
        Renderer& renderer = *machine_.renderers()[r];
        const std::size_t station = ring.position(StationKind::Renderer, r);
        for (std::uint32_t m = 0; m < phase.messages_per_renderer.at(r); ++m)
            read.emplace_back(renderer.read_out(at, words_per_message), station);
    }
    std::stable_sort(read.begin(), read.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<RingTransit> transits;
    for (const auto& [leaves, station] : read)
        transits.push_back(
            ring.transmit(leaves, RingMessage{MessageKind::Broadcast, station, 0, phase.bits_per_message, true}));
    std::sort(transits.begin(), transits.end(),
              [](const RingTransit& a, const RingTransit& b) { return a.arrival < b.arrival; });
    const GpCostModel& costs = machine_.gps().front()->costs();
    Tick taken_in = t;
    Tick receiving = 0;
    TraceRecorder* const trace = machine_.trace();
    std::vector<std::pair<Tick, Tick>> receives;  // when every GP takes each message in, for the trace
    for (const RingTransit& transit : transits) {
        const Tick receive = costs.message_receive + static_cast<Tick>(transit.words) * costs.receive_per_word;
        const Tick from = std::max(taken_in, transit.arrival);
        taken_in = from + receive;
        receiving += receive;
        if (trace != nullptr) receives.emplace_back(from, taken_in);
    }
    const std::vector<Tick> op_cost = gp_op_costs(machine_.config(), work_.op_kinds);
    Tick compute = 0;
    for (const GpOp& op : phase.then_each_gp) compute += static_cast<Tick>(op.count) * op_cost.at(op.kind);
    for (auto& gp : machine_.gps()) {
        gp->busy_ps += static_cast<std::uint64_t>(receiving + compute);
        for (const GpOp& op : phase.then_each_gp) gp->operations(work_.op_kinds[op.kind].name) += op.count;
        if (trace != nullptr) {
            const int track = trace->track("GPs", gp->name());
            for (const auto& [from, to] : receives) trace->slice(track, "taking a broadcast in", from, to);
            trace->slice(track, timing_.phases[current_].name, taken_in, taken_in + compute);
        }
    }
    timing.end_ps = taken_in + compute;
    end_phase_at(timing.end_ps);
}

}  // namespace engine

void check_picture_fits(const Machine& machine, int width, int height) {
    const FrameBuffer& fb = machine.frame_buffer();
    if (width > fb.width())
        reject_field("frame_buffer.width",
                     fmt::format("the frame buffer is {} pixels wide, the picture {}", fb.width(), width));
    if (height > fb.height())
        reject_field("frame_buffer.height",
                     fmt::format("the frame buffer is {} pixels high, the picture {}", fb.height(), height));
}

void check_gp_memory_fits(const Machine& machine, bool with_cache, std::uint64_t resident_bits,
                          const std::vector<std::uint64_t>& resident_bits_by_key) {
    const std::uint64_t cache_bits = with_cache ? machine.gps().front()->cache_bits() : 0;
    const std::size_t gp_count = machine.gps().size();
    std::vector<std::uint64_t> owned(gp_count, 0);
    for (std::size_t key = 0; key < resident_bits_by_key.size(); ++key)
        owned[key % gp_count] += resident_bits_by_key[key];
    for (std::size_t g = 0; g < gp_count; ++g) {
        const auto& gp = machine.gps()[g];
        const std::uint64_t data_bits = resident_bits + owned[g];
        const std::uint64_t need_bytes = (cache_bits + data_bits + 7) / 8;
        if (need_bytes > gp->memory_bytes())
            reject_field(
                "gp.memory_bytes",
                fmt::format("GP {} must hold its {} byte cache and {} bytes of the kernel's data ({} bytes in all), "
                            "more than its {} bytes of memory (more GPs, gp.count, would spread the data)",
                            g, cache_bits / 8, (data_bits + 7) / 8, need_bytes, gp->memory_bytes()));
    }
}

namespace {

// Busy time so far, summed over each kind of component.
struct BusyTotals {
    std::uint64_t gps = 0, renderers = 0, ring = 0;

    explicit BusyTotals(const Machine& machine) : ring(machine.ring().busy_ps()) {
        for (const auto& gp : machine.gps()) gps += gp->busy_ps.value();
        for (const auto& r : machine.renderers()) renderers += r->busy_ps.value();
    }
};

FrameActivity activity_between(const BusyTotals& before, const BusyTotals& after, const Machine& machine,
                               Tick duration) {
    const auto share = [&](std::uint64_t busy, std::size_t count) {
        const double capacity = static_cast<double>(duration) * static_cast<double>(count);
        return capacity > 0 ? static_cast<double>(busy) / capacity : 0.0;
    };
    return {share(after.gps - before.gps, machine.gps().size()),
            share(after.renderers - before.renderers, machine.renderers().size()),
            share(after.ring - before.ring, static_cast<std::size_t>(machine.ring().channel_count()))};
}

}  // namespace

FrameTiming time_frame(Machine& machine, const FrameWork& work, const EngineOptions& options) {
    const BusyTotals before(machine);
    engine::FrameRun run(machine, work);
    FrameTiming timing = run.run(options);
    timing.activity = activity_between(before, BusyTotals(machine), machine, timing.duration_ps());
    return timing;
}

}  // namespace pp5
