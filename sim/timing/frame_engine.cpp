#include "sim/timing/frame_engine.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <limits>
#include <memory>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

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

namespace {

// An event's payload: what happened (2 bits), which GP (22 bits), which block or task (40 bits).
// Arrival: a message arriving (a reply at a GP, a request at a renderer). Ready: a renderer has read
// a reply out. Task: the host's answer to a GP asking for work.
enum class Signal : std::uint64_t { Resume = 0, Arrival = 1, Task = 2, Ready = 3 };
constexpr std::uint64_t pack(Signal s, std::uint64_t gp, std::uint64_t value) {
    return (static_cast<std::uint64_t>(s) << 62) | (gp << 40) | value;
}
constexpr Signal signal_of(std::uint64_t p) { return static_cast<Signal>(p >> 62); }
constexpr std::uint64_t gp_of(std::uint64_t p) { return (p >> 40) & ((1ull << 22) - 1); }
constexpr std::uint64_t value_of(std::uint64_t p) { return p & ((1ull << 40) - 1); }
constexpr std::uint64_t kNoTask = (1ull << 40) - 1;
// A request at a renderer that is part of a GP's refresh (GpPhaseRun::refresh_lists), not one fetch: its
// value counts down from kRefreshBatch - 1 by the index of its first block in the list. Block numbers
// are 32-bit, so they never reach kRefreshFirst.
constexpr std::uint64_t kRefreshBatch = (1ull << 40) - 1;
constexpr std::uint64_t kRefreshFirst = 1ull << 32;
// A frame-buffer message that is a renderer's region read-out (the renderer's index below it), not a task's pixels.
constexpr std::uint64_t kReadout = 1ull << 63;

class GpPhaseRun;

// One GP's share of a GP phase.
class GpAgent final : public EventHandler {
public:
    GpAgent(GpPhaseRun& run, GraphicsProcessor& gp, std::size_t station);
    void begin(Tick start);
    void handle_event(Tick now, std::uint64_t payload) override;
    bool finished() const { return finished_; }
    void give_task(std::uint32_t task) { tasks_.push_back(task); }
    // A group has finished: an idle GP waiting for it goes on at `t`.
    void wake(Tick t) {
        if (!scheduled_ && !finished_ && idle_since_ >= 0) schedule_resume(t);
    }
    std::string describe_stall() const;

private:
    struct Context {
        bool active = false;
        bool waiting = false;
        bool delivered = false;  // the block of the current step arrived for this item
        std::uint32_t task = 0;
        std::uint32_t item = 0;  // within the task
        std::uint32_t step = 0;  // within the item
        std::uint32_t block = 0;
    };
    enum class Action { None, Request, AskTask, Send };
    // What a finished task sends, one message at a time: its batches in order, then its pixels.
    struct Outgoing {
        bool pixels = false;
        std::uint32_t index = 0;  // the task (pixels) or the batch
    };

    void run(Tick now);
    Tick send_refresh(Tick start);  // returns when the GP has sent it
    void perform(Tick now);
    Tick take_in_replies();
    int pick_ready_context() const;
    int start_item(Tick& t);
    // Runs context c from t; returns true when the GP must stop to act at t (send something).
    bool advance(int c, Tick& t);
    // Charges and counts `count` ops from `first` of the phase's op list.
    Tick charge(std::uint32_t first, std::uint32_t count);
    // Closes a task whose items are done: its finishing work, then what it sends (true: send the first).
    bool finish_task(std::uint32_t task, Tick& t);
    // Composes the next message of the outbox, if any (true: send it at t).
    bool queue_send(Tick& t);
    void schedule_resume(Tick t);

    GpPhaseRun& run_;
    GraphicsProcessor& gp_;
    BlockCache* cache_ = nullptr;
    std::vector<Counter*> op_counters_;  // per op kind
    std::size_t station_;
    std::vector<Context> contexts_;
    std::deque<std::uint32_t> tasks_;
    bool have_task_ = false;
    std::uint32_t task_ = 0;
    std::uint32_t next_item_ = 0;
    bool asked_for_task_ = false;
    bool no_more_tasks_ = false;
    std::unordered_map<std::uint32_t, int> outstanding_;  // block -> parts not yet arrived
    std::unordered_set<std::uint32_t> refreshing_;  // outstanding only because of a refresh: no ray has missed it yet
    std::vector<std::uint32_t> arrived_;
    std::deque<Outgoing> outbox_;
    Tick receive_cost_owed_ = 0;
    Action action_ = Action::None;
    std::uint32_t action_value_ = 0;
    bool scheduled_ = false;
    Tick idle_since_ = -1;
    bool finished_ = false;
    TraceRecorder* trace_ = nullptr;
    int trace_track_ = 0;
    int last_context_ = -1;
};

// A renderer answering fetches (queued behind its passes, read out, sent back) and, when it owns part
// of the screen, working through its region steps in order as their batches arrive.
class RendererAgent final : public EventHandler {
public:
    RendererAgent(GpPhaseRun& run, Renderer& renderer, std::size_t station);
    void handle_event(Tick now, std::uint64_t payload) override;
    void begin(Tick start);
    bool region_done() const { return next_step_ >= steps() && !drawing_; }
    std::string describe_stall() const;

private:
    std::uint32_t units_of(std::uint32_t block) const;
    std::size_t steps() const;
    // Starts the next region step if its batch is in; at the end, sends the region's pixels.
    void draw_next(Tick now);
    GpPhaseRun& run_;
    Renderer& renderer_;
    std::size_t station_;
    const RegionWork* region_ = nullptr;
    std::size_t next_step_ = 0;
    bool drawing_ = false;
    bool read_out_ = false;
    std::vector<std::uint8_t> arrived_;  // per batch of the phase (only this renderer's are set)
};

// The frame buffer: counts the pixels that arrive and when each group's last ones did.
class FrameBufferAgent final : public EventHandler {
public:
    FrameBufferAgent(GpPhaseRun& run, FrameBuffer& frame_buffer) : run_(run), frame_buffer_(frame_buffer) {}
    void handle_event(Tick now, std::uint64_t payload) override;

private:
    GpPhaseRun& run_;
    FrameBuffer& frame_buffer_;
};

// The work queue's keeper: answers each GP's request with the next task, or none.
class HostAgent final : public EventHandler {
public:
    explicit HostAgent(GpPhaseRun& run) : run_(run) {}
    void handle_event(Tick now, std::uint64_t payload) override;
    std::uint32_t next_task = 0;

private:
    GpPhaseRun& run_;
};

class FrameRun;

class GpPhaseRun {
public:
    GpPhaseRun(FrameRun& frame, Machine& machine_in, const GpPhase& phase_in, const std::vector<GpOpKind>& kinds,
               PhaseTiming& timing_in);
    void start(Tick t);

    const GpTask& task(std::uint32_t t) const { return phase.tasks[t]; }
    // No task of a group starts before every task of the groups before it has run its items.
    bool group_open(std::uint32_t group) const { return group <= groups_done; }
    void items_done(std::uint32_t task, Tick t);
    void pixels_arrived(std::uint32_t task, Tick now);
    void gp_finished(Tick now) {
        ++gps_finished;
        maybe_complete(now);
    }
    void region_finished(Tick now) {
        ++regions_finished;
        maybe_complete(now);
    }
    void readout_arrived(std::size_t renderer, Tick now);
    void maybe_complete(Tick now);
    std::string describe_stall() const;

    FrameRun& frame;
    Machine& machine;
    const GpPhase& phase;
    PhaseTiming& timing;
    std::vector<std::vector<std::uint64_t>> refresh;  // per GP: blocks to ask for again (empty: none)
    std::vector<std::vector<std::vector<std::uint32_t>>> refresh_lists;  // per GP, per renderer: what it asked for
    std::uint32_t refresh_blocks_per_message = 16;
    std::vector<Tick> op_cost;              // per op kind
    std::vector<std::string> op_names;      // per op kind
    std::vector<std::uint32_t> remaining;   // items not finished, per task
    std::vector<std::uint32_t> open_tasks;  // tasks whose items are not all done, per group
    std::uint32_t groups_done = 0;          // groups whose every task has run its items
    std::uint64_t pixel_messages_in_flight = 0;
    std::size_t gps_finished = 0;
    std::size_t regions_finished = 0;
    std::vector<std::vector<PpProgramCost>> region_costs;  // per renderer, per region program
    bool complete = false;
    std::vector<std::unique_ptr<GpAgent>> gps;
    std::vector<std::unique_ptr<RendererAgent>> renderers;
    std::unique_ptr<FrameBufferAgent> frame_buffer;
    HostAgent host;
    std::size_t frame_buffer_station = 0;
    std::size_t host_station = 0;
    int pixel_bits = 24;
    Tick renderer_busy_before = 0;
    Tick ring_busy_before = 0;
    std::uint64_t events_before = 0;
};

// The whole frame: phases one after another in one event loop.
class FrameRun final : public EventHandler {
public:
    FrameRun(Machine& machine, const FrameWork& work) : machine_(machine), work_(work) {}
    FrameTiming run(const EngineOptions& options);
    void handle_event(Tick now, std::uint64_t payload) override;  // a phase has ended
    // The current phase ends at `end`; the next starts then.
    void end_phase_at(Tick end) { machine_.events().schedule(end, *this, 0); }

private:
    void check_machine_fits() const;
    void start_phase(std::size_t index, Tick t);
    void start_pp_phase(const PpPhase& phase, PhaseTiming& timing, Tick t);
    void start_broadcast_phase(const BroadcastPhase& phase, PhaseTiming& timing, Tick t);

    Machine& machine_;
    const FrameWork& work_;
    FrameTiming timing_;
    std::size_t current_ = 0;
    std::unique_ptr<GpPhaseRun> gp_run_;
    std::vector<std::vector<std::uint64_t>> refresh_;  // per GP, for the frame's first GP phase that fetches
};

// ---------------------------------------------------------------------------------------------------
// GP agents

GpAgent::GpAgent(GpPhaseRun& run, GraphicsProcessor& gp, std::size_t station)
    : run_(run), gp_(gp), station_(station), contexts_(static_cast<std::size_t>(gp.ray_contexts())) {
    if (run.phase.blocks) cache_ = &gp.cache(run.phase.blocks->block_bits());
    op_counters_.assign(run.op_names.size(), nullptr);  // made when a kind is first done, so unused kinds list nothing
    trace_ = run.machine.trace();
    if (trace_ != nullptr) trace_track_ = trace_->track("GPs", gp.name());
}

void GpAgent::begin(Tick start) {
    if (run_.phase.assignment == TaskAssignment::WorkQueue) action_ = Action::AskTask;
    schedule_resume(send_refresh(start));
}

// The blocks this GP used in the frame before, asked for again from the renderers that hold their
// parts, a few blocks a message; until its parts are back, a block counts as on its way, as after a miss.
Tick GpAgent::send_refresh(Tick start) {
    if (run_.refresh.empty() || !run_.phase.blocks) return start;
    const std::vector<std::uint64_t>& blocks = run_.refresh[gp_.index()];
    if (blocks.empty()) return start;
    std::vector<std::vector<std::uint32_t>>& lists = run_.refresh_lists[gp_.index()];
    lists.assign(run_.renderers.size(), {});
    for (const std::uint64_t b : blocks) {
        if (b >= run_.phase.blocks->block_count()) continue;  // the volume's blocks changed: nothing to refresh
        const auto block = static_cast<std::uint32_t>(b);
        const auto parts = run_.phase.blocks->parts(block);
        for (const BlockPart& part : parts) {
            if (part.renderer >= run_.renderers.size())
                throw std::logic_error(
                    fmt::format("recorded work: block {} has a part on renderer {}, which the machine lacks", block,
                                part.renderer));
            lists[part.renderer].push_back(block);
        }
        outstanding_.emplace(block, static_cast<int>(parts.size()));
        refreshing_.insert(block);
        ++gp_.blocks_refreshed;
        ++run_.timing.gp.blocks_refreshed;
    }
    // Each renderer's list goes in messages of a few blocks, the first blocks of every list first.
    RingNetwork& ring = run_.machine.ring();
    const std::size_t per_message = std::max<std::uint32_t>(1, run_.refresh_blocks_per_message);
    Tick t = start;
    for (std::size_t first = 0;; first += per_message) {
        bool any = false;
        for (std::size_t r = 0; r < lists.size(); ++r) {
            if (first >= lists[r].size()) continue;
            any = true;
            const std::size_t count = std::min(per_message, lists[r].size() - first);
            t += gp_.costs().message_send;
            gp_.busy_ps += static_cast<std::uint64_t>(gp_.costs().message_send);
            run_.timing.gp.gp_busy += gp_.costs().message_send;
            ring.send(run_.machine.events(), t,
                      RingMessage{MessageKind::FetchRequest, station_, ring.position(StationKind::Renderer, r),
                                  static_cast<std::uint64_t>(count) * run_.phase.fetch_request_bits, false},
                      *run_.renderers[r], pack(Signal::Arrival, gp_.index(), kRefreshBatch - 1 - first));
            ++gp_.fetch_requests;
            ++run_.timing.gp.fetch_requests;
        }
        if (!any) break;
    }
    if (trace_ != nullptr && t > start) trace_->slice(trace_track_, "asking for its blocks again", start, t);
    return t;
}

void GpAgent::schedule_resume(Tick t) {
    scheduled_ = true;
    run_.machine.events().schedule(t, *this, pack(Signal::Resume, gp_.index(), 0));
}

void GpAgent::handle_event(Tick now, std::uint64_t payload) {
    switch (signal_of(payload)) {
        case Signal::Resume: run(now); return;
        case Signal::Arrival: {
            const auto block = static_cast<std::uint32_t>(value_of(payload));
            ++gp_.replies;
            const auto it = outstanding_.find(block);
            if (it == outstanding_.end())
                throw std::logic_error(fmt::format("{}: a reply nobody asked for", gp_.name()));
            const GpCostModel& costs = gp_.costs();
            receive_cost_owed_ += costs.message_receive;
            if (--it->second == 0) {
                // The whole block is in: copy its words into the cache.
                const BlockDirectory& blocks = *run_.phase.blocks;
                std::uint64_t words = 0;
                for (const BlockPart& part : blocks.parts(block))
                    words +=
                        run_.machine.ring().message_words(static_cast<std::uint64_t>(part.units) * blocks.unit_bits());
                receive_cost_owed_ += static_cast<Tick>(words) * costs.receive_per_word;
                arrived_.push_back(block);
                outstanding_.erase(it);
            }
            if (!scheduled_ && !finished_) run(now);
            return;
        }
        case Signal::Task: {
            asked_for_task_ = false;
            const std::uint64_t task = value_of(payload);
            if (task == kNoTask) no_more_tasks_ = true;
            else tasks_.push_back(static_cast<std::uint32_t>(task));
            if (!scheduled_ && !finished_) run(now);
            return;
        }
        case Signal::Ready: break;
    }
    throw std::logic_error("GP agent: unexpected event");
}

void GpAgent::perform(Tick now) {
    RingNetwork& ring = run_.machine.ring();
    EventQueue& events = run_.machine.events();
    switch (action_) {
        case Action::None: break;
        case Action::Request:
            for (const BlockPart& part : run_.phase.blocks->parts(action_value_)) {
                // Checked here, where a block is first asked for, not over the whole directory every frame.
                if (part.renderer >= run_.renderers.size())
                    throw std::logic_error(
                        fmt::format("recorded work: block {} has a part on renderer {}, which the machine lacks",
                                    action_value_, part.renderer));
                const std::size_t to = ring.position(StationKind::Renderer, part.renderer);
                ring.send(events, now,
                          RingMessage{MessageKind::FetchRequest, station_, to, run_.phase.fetch_request_bits, false},
                          *run_.renderers[part.renderer], pack(Signal::Arrival, gp_.index(), action_value_));
                ++gp_.fetch_requests;
                ++run_.timing.gp.fetch_requests;
            }
            break;
        case Action::Send: {
            const Outgoing out = outbox_.front();
            outbox_.pop_front();
            if (out.pixels) {
                const GpTask& task = run_.task(out.index);
                ++run_.pixel_messages_in_flight;
                ring.send(
                    events, now,
                    RingMessage{MessageKind::PixelBlock, station_, run_.frame_buffer_station,
                                static_cast<std::uint64_t>(task.pixels) * static_cast<std::uint64_t>(run_.pixel_bits),
                                false},
                    *run_.frame_buffer, out.index);
            } else {
                const PrimitiveBatch& batch = run_.phase.batches[out.index];
                ring.send(events, now,
                          RingMessage{MessageKind::PrimitiveBatch, station_,
                                      ring.position(StationKind::Renderer, batch.renderer), batch.bits, false},
                          *run_.renderers[batch.renderer], pack(Signal::Task, gp_.index(), out.index));
                ++run_.timing.gp.batches_sent;
                run_.timing.gp.batch_bits += batch.bits;
            }
            break;
        }
        case Action::AskTask:
            asked_for_task_ = true;
            ring.send(events, now, RingMessage{MessageKind::Command, station_, run_.host_station, 32, false}, run_.host,
                      pack(Signal::Task, gp_.index(), 0));
            break;
    }
    action_ = Action::None;
}

Tick GpAgent::take_in_replies() {
    Tick cost = receive_cost_owed_;
    receive_cost_owed_ = 0;
    for (const std::uint32_t block : arrived_) {
        cache_->insert(block, refreshing_.erase(block) == 0);  // a refreshed copy no ray waited for is not yet a use
        for (Context& c : contexts_) {
            if (c.active && c.waiting && c.block == block) {
                c.waiting = false;
                c.delivered = true;
            }
        }
    }
    arrived_.clear();
    return cost;
}

int GpAgent::pick_ready_context() const {
    const int n = static_cast<int>(contexts_.size());
    for (int i = 1; i <= n; ++i) {
        const int c = (last_context_ + i + n) % n;
        if (contexts_[static_cast<std::size_t>(c)].active && !contexts_[static_cast<std::size_t>(c)].waiting) return c;
    }
    return -1;
}

Tick GpAgent::charge(std::uint32_t first, std::uint32_t count) {
    Tick t = 0;
    for (std::uint32_t i = first; i < first + count; ++i) {
        const GpOp& op = run_.phase.ops[i];
        t += static_cast<Tick>(op.count) * run_.op_cost[op.kind];
        Counter*& counter = op_counters_[op.kind];
        if (counter == nullptr) counter = &gp_.operations(run_.op_names[op.kind]);
        *counter += op.count;
    }
    return t;
}

bool GpAgent::finish_task(std::uint32_t task_index, Tick& t) {
    const GpTask& task = run_.task(task_index);
    run_.items_done(task_index, t);
    t += charge(task.first_finish_op, task.finish_op_count);
    ++gp_.tasks;
    for (std::uint32_t b = task.first_batch; b < task.first_batch + task.batch_count; ++b)
        outbox_.push_back(Outgoing{false, b});
    if (task.pixels > 0) outbox_.push_back(Outgoing{true, task_index});
    return queue_send(t);
}

bool GpAgent::queue_send(Tick& t) {
    if (outbox_.empty()) return false;
    t += gp_.costs().message_send;
    action_ = Action::Send;
    return true;
}

int GpAgent::start_item(Tick& t) {
    const auto free = std::find_if(contexts_.begin(), contexts_.end(), [](const Context& c) { return !c.active; });
    if (free == contexts_.end()) return -1;
    while (!have_task_ || next_item_ >= run_.task(task_).item_count) {
        if (tasks_.empty()) {
            // Ask the host for more work while the items in flight go on.
            if (run_.phase.assignment == TaskAssignment::WorkQueue && !asked_for_task_ && !no_more_tasks_)
                action_ = Action::AskTask;
            return -1;
        }
        if (!run_.group_open(run_.task(tasks_.front()).group)) return -1;  // wait for the group before
        task_ = tasks_.front();
        tasks_.pop_front();
        run_.timing.task_gp[task_] = static_cast<std::uint32_t>(gp_.index());
        have_task_ = true;
        next_item_ = 0;
        const GpTask& task = run_.task(task_);
        t += charge(task.first_op, task.op_count);
        if (task.item_count == 0 && finish_task(task_, t)) return -1;  // its pixels go first
    }
    Context& c = *free;
    c = Context{};
    c.active = true;
    c.task = task_;
    c.item = next_item_++;
    return static_cast<int>(free - contexts_.begin());
}

bool GpAgent::advance(int index, Tick& t) {
    Context& c = contexts_[static_cast<std::size_t>(index)];
    const GpTask& task = run_.task(c.task);
    const GpItem& item = run_.phase.items[task.first_item + c.item];
    const GpCostModel& costs = gp_.costs();
    while (c.step < item.step_count) {
        const GpStep& step = run_.phase.steps[item.first_step + c.step];
        if (!c.delivered) {
            t += charge(step.first_op, step.op_count);
            if (step.block != kNoFetch) {
                t += costs.cache_lookup;
                if (!cache_->lookup(step.block)) {
                    ++run_.timing.gp.cache_misses;
                    c.waiting = true;
                    c.block = step.block;
                    if (outstanding_.count(step.block) != 0) {  // on its way (asked for, or being refreshed)
                        refreshing_.erase(step.block);          // a ray waits for it now
                        return false;
                    }
                    const auto parts = run_.phase.blocks->parts(step.block);
                    outstanding_.emplace(step.block, static_cast<int>(parts.size()));
                    t += static_cast<Tick>(parts.size()) * costs.message_send;
                    action_ = Action::Request;
                    action_value_ = step.block;
                    return true;
                }
                ++run_.timing.gp.cache_hits;
            }
        }
        c.delivered = false;
        ++c.step;
    }
    c.active = false;
    ++gp_.items;
    ++run_.timing.gp.items;
    if (--run_.remaining[c.task] == 0) return finish_task(c.task, t);
    return false;
}

void GpAgent::run(Tick now) {
    scheduled_ = false;
    if (idle_since_ >= 0) {
        const Tick waited = now - idle_since_;
        gp_.wait_ps += static_cast<std::uint64_t>(waited);
        run_.timing.gp.gp_wait += waited;
        if (trace_ != nullptr && waited > 0) trace_->slice(trace_track_, "waiting", idle_since_, now);
        idle_since_ = -1;
    }
    perform(now);
    Tick t = now + take_in_replies();
    // A finished task's messages go out one by one before any other work.
    if (!queue_send(t)) {
        for (;;) {
            // At a switch, replies or a task that arrived meanwhile are taken in: stop here and let the
            // events before t run first.
            if (t > now && (!outstanding_.empty() || asked_for_task_) && run_.machine.events().next_time() <= t) break;
            int c = pick_ready_context();
            if (c < 0) c = start_item(t);
            if (c < 0) break;
            if (last_context_ >= 0 && c != last_context_) {
                t += gp_.costs().context_switch;
                ++gp_.context_switches;
                ++run_.timing.gp.context_switches;
            }
            last_context_ = c;
            if (advance(c, t)) break;
        }
    }
    gp_.busy_ps += static_cast<std::uint64_t>(t - now);
    run_.timing.gp.gp_busy += t - now;
    if (trace_ != nullptr && t > now) trace_->slice(trace_track_, "computing", now, t);
    if (action_ != Action::None || t > now) {
        schedule_resume(t);
        return;
    }
    const bool in_flight = std::any_of(contexts_.begin(), contexts_.end(), [](const Context& c) { return c.active; });
    const bool more_in_task = have_task_ && next_item_ < run_.task(task_).item_count;
    const bool more_tasks = !tasks_.empty() || (run_.phase.assignment == TaskAssignment::WorkQueue && !no_more_tasks_);
    if (!in_flight && !more_in_task && !more_tasks) {
        finished_ = true;
        run_.gp_finished(now);
        return;
    }
    idle_since_ = now;  // every item waits for a block, or the GP waits for a task or a group
}

std::string GpAgent::describe_stall() const {
    std::string why = fmt::format("{}:", gp_.name());
    for (std::size_t i = 0; i < contexts_.size(); ++i) {
        const Context& c = contexts_[i];
        if (c.active && c.waiting)
            why += fmt::format(" context {} (task {}, item {}) waits for block {};", i, c.task, c.item, c.block);
    }
    for (const auto& [block, parts_left] : outstanding_)
        why += fmt::format(" block {} has {} part(s) outstanding;", block, parts_left);
    if (asked_for_task_) why += " it waits for a task from the host;";
    if (!tasks_.empty() && !run_.group_open(run_.task(tasks_.front()).group))
        why += fmt::format(" it waits for group {} to finish;", run_.task(tasks_.front()).group - 1);
    if (!arrived_.empty()) why += " replies arrived but were not taken in;";
    return why;
}

// ---------------------------------------------------------------------------------------------------
// Renderers, frame buffer, host

std::uint32_t RendererAgent::units_of(std::uint32_t block) const {
    for (const BlockPart& part : run_.phase.blocks->parts(block))
        if (part.renderer == renderer_.index()) return part.units;
    throw std::logic_error(fmt::format("{}: asked for a block it holds no part of", renderer_.name()));
}

RendererAgent::RendererAgent(GpPhaseRun& run, Renderer& renderer, std::size_t station)
    : run_(run), renderer_(renderer), station_(station) {
    if (renderer.index() < run.phase.regions.size()) region_ = &run.phase.regions[renderer.index()];
    if (region_ != nullptr && !region_->steps.empty()) arrived_.assign(run.phase.batches.size(), 0);
}

std::size_t RendererAgent::steps() const { return region_ == nullptr ? 0 : region_->steps.size(); }

void RendererAgent::begin(Tick start) {
    if (region_ == nullptr) run_.region_finished(start);  // no screen work here this phase
    else draw_next(start);
}

void RendererAgent::draw_next(Tick now) {
    if (drawing_) return;
    if (next_step_ < steps()) {
        const RegionStep& step = region_->steps[next_step_];
        if (step.batch != kNoBatch && !arrived_[step.batch]) return;  // the batch it draws is not in yet
        ++next_step_;
        const PpProgram& program = run_.phase.region_programs[step.program];
        const auto busy_before = renderer_.draw_busy_ps.value();
        const Tick end = renderer_.draw(now, program.name, run_.region_costs[renderer_.index()][step.program],
                                        step.runs, step.write_words, program.local_memory_bits_used);
        run_.timing.gp.primitives_drawn += step.runs;
        run_.timing.gp.renderer_drawing[renderer_.index()] +=
            static_cast<Tick>(renderer_.draw_busy_ps.value() - busy_before);
        drawing_ = true;
        run_.machine.events().schedule(end, *this, pack(Signal::Resume, 0, 0));
        return;
    }
    if (read_out_) return;
    read_out_ = true;
    if (region_->readout_pixels > 0) {
        ++run_.pixel_messages_in_flight;
        RingNetwork& ring = run_.machine.ring();
        ring.send(run_.machine.events(), std::max(now, renderer_.busy_until()),
                  RingMessage{MessageKind::PixelBlock, station_, run_.frame_buffer_station,
                              region_->readout_pixels * static_cast<std::uint64_t>(run_.pixel_bits), false},
                  *run_.frame_buffer, kReadout | renderer_.index());
    }
    run_.region_finished(now);
}

std::string RendererAgent::describe_stall() const {
    if (region_done()) return {};
    if (drawing_) return fmt::format(" {} is drawing step {};", renderer_.name(), next_step_ - 1);
    return fmt::format(" {} waits for batch {} (region step {} of {});", renderer_.name(),
                       region_->steps[next_step_].batch, next_step_, steps());
}

void RendererAgent::handle_event(Tick now, std::uint64_t payload) {
    if (signal_of(payload) == Signal::Task) {  // a batch for this renderer's region has arrived
        const auto batch = static_cast<std::uint32_t>(value_of(payload));
        if (arrived_.empty())
            throw std::logic_error(
                fmt::format("{}: a primitive batch for a renderer with no region work", renderer_.name()));
        arrived_[batch] = 1;
        draw_next(now);
        return;
    }
    if (signal_of(payload) == Signal::Resume) {  // a region step is done
        drawing_ = false;
        draw_next(now);
        return;
    }
    const auto gp = gp_of(payload);
    const auto block = static_cast<std::uint32_t>(value_of(payload));
    if (signal_of(payload) == Signal::Arrival &&
        value_of(payload) >= kRefreshFirst) {  // a GP's refresh: one setup, a reply a block
        const std::vector<std::uint32_t>& list = run_.refresh_lists[gp][renderer_.index()];
        const std::size_t first = kRefreshBatch - 1 - value_of(payload);
        const std::size_t end =
            std::min(list.size(), first + std::max<std::uint32_t>(1, run_.refresh_blocks_per_message));
        for (std::size_t i = first; i < end; ++i) {
            const Tick ready = renderer_.serve_fetch(now, units_of(list[i]), i == first);
            run_.machine.events().schedule(ready, *this, pack(Signal::Ready, gp, list[i]));
        }
        return;
    }
    if (signal_of(payload) == Signal::Arrival) {  // a request has arrived: queue it
        const Tick ready = renderer_.serve_fetch(now, units_of(block));
        run_.machine.events().schedule(ready, *this, pack(Signal::Ready, gp, block));
        return;
    }
    // The reply is read out: send it.
    const std::uint64_t bits = static_cast<std::uint64_t>(units_of(block)) * run_.phase.blocks->unit_bits();
    RingNetwork& ring = run_.machine.ring();
    ring.send(
        run_.machine.events(), now,
        RingMessage{MessageKind::FetchReply, station_, ring.position(StationKind::GraphicsProcessor, gp), bits, false},
        *run_.gps[gp], pack(Signal::Arrival, gp, block));
}

void FrameBufferAgent::handle_event(Tick now, std::uint64_t payload) {
    if ((payload & kReadout) != 0) {
        const std::size_t renderer = payload & ~kReadout;
        frame_buffer_.pixels_written += run_.phase.regions[renderer].readout_pixels;
        run_.readout_arrived(renderer, now);
        return;
    }
    const auto task = static_cast<std::uint32_t>(payload);
    frame_buffer_.pixels_written += run_.task(task).pixels;
    run_.pixels_arrived(task, now);
}

void HostAgent::handle_event(Tick now, std::uint64_t payload) {
    const auto gp = gp_of(payload);
    std::uint64_t task = kNoTask;
    if (next_task < run_.phase.tasks.size()) task = next_task++;
    RingNetwork& ring = run_.machine.ring();
    ring.send(run_.machine.events(), now,
              RingMessage{MessageKind::Command, run_.host_station, ring.position(StationKind::GraphicsProcessor, gp),
                          32, false},
              *run_.gps[gp], pack(Signal::Task, gp, task));
}

// ---------------------------------------------------------------------------------------------------
// A GP phase

Tick renderers_answering(Machine& machine) {
    Tick total = 0;
    for (const auto& r : machine.renderers()) total += static_cast<Tick>(r->fetch_busy_ps.value());
    return total;
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
    renderer_busy_before = renderers_answering(machine);
    ring_busy_before = static_cast<Tick>(machine.ring().busy_ps());
    events_before = machine.events().events_run();
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
    timing.gp.renderer_busy = renderers_answering(machine) - renderer_busy_before;
    timing.gp.ring_busy = static_cast<Tick>(machine.ring().busy_ps()) - ring_busy_before;
    timing.gp.events = machine.events().events_run() - events_before;
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

// ---------------------------------------------------------------------------------------------------
// The frame

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
        p.instructions = work.program.instructions.size();
        p.local_memory_bits_used = work.program.local_memory_bits_used;
        for (std::size_t r = 0; r < renderers.size(); ++r) {
            Renderer& renderer = *renderers[r];
            const RendererPass run{work.program.name, renderer.cost_model().cost(work.program), work.slots[r],
                                   work.counts[r], work.program.local_memory_bits_used};
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

}  // namespace

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

FrameTiming time_frame(Machine& machine, const FrameWork& work, const EngineOptions& options) {
    FrameRun run(machine, work);
    return run.run(options);
}

}  // namespace pp5
