#pragma once
// The timing engine's parts (frame_engine.h says what the engine does): the event payloads, an agent
// per GP, renderer, frame buffer and the host's work queue, the run of one GP phase that they share,
// and the run of a whole frame. Internal to sim/timing: the engine's users include frame_engine.h.
//
// Where each is defined: gp_agent.cpp (a GP working through its tasks), station_agents.cpp (the
// renderers, the frame buffer and the host), gp_phase_run.cpp (one GP phase), frame_engine.cpp (the
// frame, phase after phase).

#include "sim/timing/frame_engine.h"

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace pp5::engine {

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

// What a GP phase reports of the components' counters, summed over them: its counts are the
// difference between their values as it ends and as it begins, so the components keep the one set
// of books.
struct MachineCounters {
    std::uint64_t items = 0, cache_hits = 0, cache_misses = 0, fetch_requests = 0, blocks_refreshed = 0,
                  context_switches = 0, events = 0;
    Tick gp_busy = 0, gp_wait = 0, renderer_busy = 0, ring_busy = 0;

    static MachineCounters of(Machine& machine);
};

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
    MachineCounters at_start;  // the components' counters as the phase began
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

}  // namespace pp5::engine
