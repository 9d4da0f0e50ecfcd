#include "kernels/levoy/ray_cast_timing.h"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <memory>
#include <stdexcept>

namespace pp5 {

std::string to_string(RayAssignment assignment) {
    return assignment == RayAssignment::StaticTiles ? "static_tiles" : "work_queue";
}

namespace {

// An event's payload: what happened (2 bits), which GP (22 bits), which block or task (40 bits).
// Arrival is a message arriving: a reply at a GP, a request at a renderer. Ready: a renderer has read
// a reply out. Task: the host's answer to a GP asking for work.
enum class Signal : std::uint64_t { Resume = 0, Arrival = 1, Task = 2, Ready = 3 };
constexpr std::uint64_t pack(Signal s, std::uint64_t gp, std::uint64_t value) {
    return (static_cast<std::uint64_t>(s) << 62) | (gp << 40) | value;
}
constexpr Signal signal_of(std::uint64_t p) { return static_cast<Signal>(p >> 62); }
constexpr std::uint64_t gp_of(std::uint64_t p) { return (p >> 40) & ((1ull << 22) - 1); }
constexpr std::uint64_t value_of(std::uint64_t p) { return p & ((1ull << 40) - 1); }
constexpr std::uint64_t kNoTask = (1ull << 40) - 1;

class Engine;

class GpAgent final : public EventHandler {
public:
    GpAgent(Engine& engine, GraphicsProcessor& gp, std::size_t station);
    void begin(Tick start);
    void handle_event(Tick now, std::uint64_t payload) override;
    bool finished() const { return finished_; }
    void give_task(std::uint32_t task) { tasks_.push_back(task); }
    // A refinement pass has finished: an idle GP waiting for it goes on at `t`.
    void wake(Tick t) {
        if (!scheduled_ && !finished_ && idle_since_ >= 0) schedule_resume(t);
    }
    std::string describe_stall() const;

private:
    struct Context {
        bool active = false;
        bool waiting = false;
        bool delivered = false;  // the block of the current touch arrived for this ray
        std::uint32_t task = 0;
        std::uint32_t ray = 0;  // within the task's pass batch
        std::uint32_t touch = 0;
        std::uint32_t block = 0;
    };
    struct Outstanding {
        std::uint32_t block;
        int parts_left;
    };
    enum class Action { None, Request, Pixels, AskTask };

    void run(Tick now);
    void perform(Tick now);
    Tick take_in_replies();
    int pick_ready_context() const;
    int start_ray(Tick& t);
    // Runs context c from t; returns true when the GP must stop to act at t (send something).
    bool advance(int c, Tick& t);
    void schedule_resume(Tick t);

    Engine& engine_;
    GraphicsProcessor& gp_;
    VoxelCache* cache_ = nullptr;
    std::size_t station_;
    std::vector<Context> contexts_;
    std::deque<std::uint32_t> tasks_;
    bool have_task_ = false;
    std::uint32_t task_ = 0;
    std::uint32_t next_ray_ = 0;
    bool asked_for_task_ = false;
    bool no_more_tasks_ = false;
    std::vector<Outstanding> outstanding_;
    std::vector<std::uint32_t> arrived_;
    Tick receive_cost_owed_ = 0;
    Action action_ = Action::None;
    std::uint32_t action_value_ = 0;
    bool scheduled_ = false;
    Tick idle_since_ = -1;
    bool finished_ = false;
    TraceRecorder* trace_ = nullptr;
    int trace_track_ = 0;
    int last_context_ = -1;
    friend class Engine;
};

class RendererAgent final : public EventHandler {
public:
    RendererAgent(Engine& engine, Renderer& renderer, std::size_t station) : engine_(engine), renderer_(renderer), station_(station) {}
    void handle_event(Tick now, std::uint64_t payload) override;

private:
    std::uint32_t voxels_of(std::uint32_t block) const;
    Engine& engine_;
    Renderer& renderer_;
    std::size_t station_;
};

class FrameBufferAgent final : public EventHandler {
public:
    explicit FrameBufferAgent(std::size_t passes) : pass_end(passes, 0), tiles_in(passes, 0) {}
    void handle_event(Tick now, std::uint64_t payload) override {
        const auto pass = static_cast<std::size_t>(payload);
        pass_end[pass] = std::max(pass_end[pass], now);
        ++tiles_in[pass];
    }
    std::vector<Tick> pass_end;
    std::vector<std::uint32_t> tiles_in;
};

// The work queue's keeper: answers each GP's request with the next task, or none.
class HostAgent final : public EventHandler {
public:
    explicit HostAgent(Engine& engine) : engine_(engine) {}
    void handle_event(Tick now, std::uint64_t payload) override;
    std::uint32_t next_task = 0;

private:
    Engine& engine_;
};

class Engine {
public:
    Engine(Machine& machine_in, VoxelBlocks& blocks_in, const RayCastJob& job_in, const RayCastTimingOptions& options_in)
        : machine(machine_in), blocks(blocks_in), job(job_in), options(options_in), frame_buffer(job_in.passes.size()), host(*this) {
        remaining.resize(job.tasks.size());
        open_tasks.assign(job.passes.size(), 0);
        for (std::size_t i = 0; i < job.tasks.size(); ++i) {
            remaining[i] = job.tasks[i].ray_count;
            ++open_tasks.at(static_cast<std::size_t>(job.tasks[i].pass));
        }
        while (passes_done < open_tasks.size() && open_tasks[passes_done] == 0) ++passes_done;
        RingNetwork& ring = machine.ring();
        for (auto& gp : machine.gps())
            gps.push_back(std::make_unique<GpAgent>(*this, *gp, ring.position(StationKind::GraphicsProcessor, gp->index())));
        for (auto& r : machine.renderers())
            renderers.push_back(std::make_unique<RendererAgent>(*this, *r, ring.position(StationKind::Renderer, r->index())));
        frame_buffer_station = ring.position(StationKind::FrameBuffer, 0);
        host_station = ring.position(StationKind::Host, 0);
    }

    const CastBatch& batch_of(std::uint32_t task) const { return job.passes[static_cast<std::size_t>(job.tasks[task].pass)]; }
    const RayWork& ray(std::uint32_t task, std::uint32_t r) const { return batch_of(task).rays[job.tasks[task].first_ray + r]; }

    Machine& machine;
    VoxelBlocks& blocks;
    const RayCastJob& job;
    const RayCastTimingOptions& options;
    // A pass's rays are chosen from the colours of the pass before, all over the image: no task of a
    // pass starts before every task of the passes before it has finished.
    bool pass_open(int pass) const { return static_cast<std::size_t>(pass) <= passes_done; }
    void task_done(std::uint32_t task, Tick t) {
        --open_tasks[static_cast<std::size_t>(job.tasks[task].pass)];
        const std::size_t before = passes_done;
        while (passes_done < open_tasks.size() && open_tasks[passes_done] == 0) ++passes_done;
        if (passes_done != before)
            for (auto& gp : gps) gp->wake(t);
    }

    std::vector<std::uint32_t> remaining;  // rays not finished, per task
    std::vector<std::uint32_t> open_tasks; // tasks not finished, per pass
    std::size_t passes_done = 0;           // passes whose every task has finished
    std::vector<std::unique_ptr<GpAgent>> gps;
    std::vector<std::unique_ptr<RendererAgent>> renderers;
    FrameBufferAgent frame_buffer;
    HostAgent host;
    std::size_t frame_buffer_station = 0;
    std::size_t host_station = 0;
    RayCastReport report;
};

GpAgent::GpAgent(Engine& engine, GraphicsProcessor& gp, std::size_t station)
    : engine_(engine), gp_(gp), station_(station), contexts_(static_cast<std::size_t>(gp.ray_contexts())) {
    cache_ = &gp.cache(engine.blocks.block_bits());
    trace_ = engine.machine.trace();
    if (trace_ != nullptr) trace_track_ = trace_->track("GPs", gp.name());
}

void GpAgent::begin(Tick start) {
    if (engine_.options.assignment == RayAssignment::WorkQueue) action_ = Action::AskTask;
    schedule_resume(start);
}

void GpAgent::schedule_resume(Tick t) {
    scheduled_ = true;
    engine_.machine.events().schedule(t, *this, pack(Signal::Resume, gp_.index(), 0));
}

void GpAgent::handle_event(Tick now, std::uint64_t payload) {
    switch (signal_of(payload)) {
        case Signal::Resume:
            run(now);
            return;
        case Signal::Arrival: {
            const auto block = static_cast<std::uint32_t>(value_of(payload));
            ++gp_.replies;
            const auto it = std::find_if(outstanding_.begin(), outstanding_.end(), [&](const Outstanding& o) { return o.block == block; });
            if (it == outstanding_.end()) throw std::logic_error(fmt::format("{}: a reply nobody asked for", gp_.name()));
            const GpCostModel& costs = gp_.costs();
            receive_cost_owed_ += costs.message_receive;
            if (--it->parts_left == 0) {
                // The whole block is in: copy its words into the cache.
                std::uint64_t words = 0;
                for (const auto& part : engine_.blocks.parts(block))
                    words += engine_.machine.ring().message_words(static_cast<std::uint64_t>(part.voxels) *
                                                                  static_cast<std::uint64_t>(engine_.blocks.voxel_bits()));
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
    RingNetwork& ring = engine_.machine.ring();
    EventQueue& events = engine_.machine.events();
    switch (action_) {
        case Action::None: break;
        case Action::Request:
            for (const auto& part : engine_.blocks.parts(action_value_)) {
                const std::size_t to = ring.position(StationKind::Renderer, static_cast<std::size_t>(part.renderer));
                ring.send(events, now, RingMessage{MessageKind::VoxelRequest, station_, to, static_cast<std::uint64_t>(engine_.options.request_bits), false},
                          *engine_.renderers[static_cast<std::size_t>(part.renderer)], pack(Signal::Arrival, gp_.index(), action_value_));
                ++gp_.requests;
                ++engine_.report.requests;
            }
            break;
        case Action::Pixels: {
            const TileTask& task = engine_.job.tasks[action_value_];
            ring.send(events, now, RingMessage{MessageKind::Pixels, station_, engine_.frame_buffer_station,
                                               static_cast<std::uint64_t>(task.tile_pixels) * static_cast<std::uint64_t>(engine_.options.pixel_bits), false},
                      engine_.frame_buffer, static_cast<std::uint64_t>(task.pass));
            break;
        }
        case Action::AskTask:
            asked_for_task_ = true;
            ring.send(events, now, RingMessage{MessageKind::Command, station_, engine_.host_station, 32, false}, engine_.host,
                      pack(Signal::Task, gp_.index(), 0));
            break;
    }
    action_ = Action::None;
}

Tick GpAgent::take_in_replies() {
    Tick cost = receive_cost_owed_;
    receive_cost_owed_ = 0;
    for (const std::uint32_t block : arrived_) {
        cache_->insert(block);
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

int GpAgent::start_ray(Tick& t) {
    const auto free = std::find_if(contexts_.begin(), contexts_.end(), [](const Context& c) { return !c.active; });
    if (free == contexts_.end()) return -1;
    while (!have_task_ || next_ray_ >= engine_.job.tasks[task_].ray_count) {
        if (tasks_.empty()) {
            // Ask the host for more work while the rays in flight go on.
            if (engine_.options.assignment == RayAssignment::WorkQueue && !asked_for_task_ && !no_more_tasks_) action_ = Action::AskTask;
            return -1;
        }
        if (!engine_.pass_open(engine_.job.tasks[tasks_.front()].pass)) return -1;  // wait for the pass before
        task_ = tasks_.front();
        tasks_.pop_front();
        have_task_ = true;
        next_ray_ = 0;
        const TileTask& task = engine_.job.tasks[task_];
        t += static_cast<Tick>(task.squares_tested) * gp_.costs().refinement_test;
        if (task.ray_count == 0) engine_.task_done(task_, t);  // only refinement tests
    }
    Context& c = *free;
    c = Context{};
    c.active = true;
    c.task = task_;
    c.ray = next_ray_++;
    t += gp_.costs().ray_setup;
    return static_cast<int>(free - contexts_.begin());
}

bool GpAgent::advance(int index, Tick& t) {
    Context& c = contexts_[static_cast<std::size_t>(index)];
    const CastBatch& batch = engine_.batch_of(c.task);
    const RayWork& ray = engine_.ray(c.task, c.ray);
    const GpCostModel& costs = gp_.costs();
    while (c.touch < ray.touch_count) {
        const BlockTouch& touch = batch.touches[ray.first_touch + c.touch];
        if (!c.delivered) {
            t += static_cast<Tick>(touch.samples) * costs.per_sample() + static_cast<Tick>(touch.pyramid_steps) * costs.pyramid_step +
                 costs.cache_lookup;
            if (!cache_->lookup(touch.block)) {
                ++engine_.report.cache_misses;
                c.waiting = true;
                c.block = touch.block;
                const bool on_its_way = std::any_of(outstanding_.begin(), outstanding_.end(),
                                                    [&](const Outstanding& o) { return o.block == touch.block; });
                if (on_its_way) return false;
                const auto parts = engine_.blocks.parts(touch.block);
                outstanding_.push_back(Outstanding{touch.block, static_cast<int>(parts.size())});
                t += static_cast<Tick>(parts.size()) * costs.message_send;
                action_ = Action::Request;
                action_value_ = touch.block;
                return true;
            }
            ++engine_.report.cache_hits;
        }
        c.delivered = false;
        ++c.touch;
    }
    // The rest of the ray, then its pixel.
    t += static_cast<Tick>(ray.tail_samples) * costs.per_sample() + static_cast<Tick>(ray.tail_pyramid_steps) * costs.pyramid_step;
    c.active = false;
    ++gp_.rays;
    gp_.samples += ray.samples;
    gp_.samples_skipped += ray.samples_skipped;
    gp_.pyramid_steps += ray.pyramid_steps;
    RayCastReport& report = engine_.report;
    ++report.rays;
    report.samples += ray.samples;
    report.samples_skipped += ray.samples_skipped;
    report.pyramid_steps += ray.pyramid_steps;
    if (ray.terminated) {
        ++gp_.rays_terminated;
        ++report.rays_terminated;
    }
    if (--engine_.remaining[c.task] == 0) {
        const TileTask& task = engine_.job.tasks[c.task];
        engine_.task_done(c.task, t);
        t += static_cast<Tick>(task.pixels_filled) * costs.pixel_fill + costs.message_send;
        gp_.pixels_filled += task.pixels_filled;
        report.pixels_filled += task.pixels_filled;
        action_ = Action::Pixels;
        action_value_ = c.task;
        return true;
    }
    return false;
}

void GpAgent::run(Tick now) {
    scheduled_ = false;
    if (idle_since_ >= 0) {
        const Tick waited = now - idle_since_;
        gp_.wait_ps += static_cast<std::uint64_t>(waited);
        engine_.report.gp_wait += waited;
        if (trace_ != nullptr && waited > 0) trace_->slice(trace_track_, "waiting", idle_since_, now);
        idle_since_ = -1;
    }
    perform(now);
    Tick t = now + take_in_replies();
    for (;;) {
        // At a switch, replies or a task that arrived meanwhile are taken in: stop here and let the
        // events before t run first.
        if (t > now && (!outstanding_.empty() || asked_for_task_) && engine_.machine.events().next_time() <= t) break;
        int c = pick_ready_context();
        if (c < 0) c = start_ray(t);
        if (c < 0) break;
        if (last_context_ >= 0 && c != last_context_) {
            t += gp_.costs().context_switch;
            ++gp_.context_switches;
            ++engine_.report.context_switches;
        }
        last_context_ = c;
        if (advance(c, t)) break;
    }
    gp_.busy_ps += static_cast<std::uint64_t>(t - now);
    engine_.report.gp_busy += t - now;
    if (trace_ != nullptr && t > now) trace_->slice(trace_track_, "computing", now, t);
    if (action_ != Action::None || t > now) {
        schedule_resume(t);
        return;
    }
    const bool rays_in_flight = std::any_of(contexts_.begin(), contexts_.end(), [](const Context& c) { return c.active; });
    const bool more_in_task = have_task_ && next_ray_ < engine_.job.tasks[task_].ray_count;
    const bool more_tasks = !tasks_.empty() || (engine_.options.assignment == RayAssignment::WorkQueue && !no_more_tasks_);
    if (!rays_in_flight && !more_in_task && !more_tasks) {
        finished_ = true;
        return;
    }
    idle_since_ = now;  // every ray waits for voxels, or the GP waits for a task
}

std::string GpAgent::describe_stall() const {
    std::string why = fmt::format("{}:", gp_.name());
    for (std::size_t i = 0; i < contexts_.size(); ++i) {
        const Context& c = contexts_[i];
        if (c.active && c.waiting) why += fmt::format(" ray context {} waits for voxel block {};", i, c.block);
    }
    for (const Outstanding& o : outstanding_) why += fmt::format(" block {} has {} part(s) outstanding;", o.block, o.parts_left);
    if (asked_for_task_) why += " it waits for a task from the host;";
    if (!tasks_.empty() && !engine_.pass_open(engine_.job.tasks[tasks_.front()].pass))
        why += fmt::format(" it waits for refinement pass {} to finish;", engine_.job.tasks[tasks_.front()].pass - 1);
    if (!arrived_.empty()) why += " replies arrived but were not taken in;";
    return why;
}

std::uint32_t RendererAgent::voxels_of(std::uint32_t block) const {
    for (const auto& part : engine_.blocks.parts(block))
        if (static_cast<std::size_t>(part.renderer) == renderer_.index()) return part.voxels;
    throw std::logic_error(fmt::format("{}: asked for a block it holds no voxel of", renderer_.name()));
}

void RendererAgent::handle_event(Tick now, std::uint64_t payload) {
    const auto gp = gp_of(payload);
    const auto block = static_cast<std::uint32_t>(value_of(payload));
    if (signal_of(payload) == Signal::Arrival) {  // a request has arrived: queue it
        const Tick ready = renderer_.serve_request(now, voxels_of(block));
        engine_.machine.events().schedule(ready, *this, pack(Signal::Ready, gp, block));
        return;
    }
    // The reply is read out: send it.
    const std::uint64_t bits = static_cast<std::uint64_t>(voxels_of(block)) * static_cast<std::uint64_t>(engine_.blocks.voxel_bits());
    RingNetwork& ring = engine_.machine.ring();
    GpAgent& to = *engine_.gps[gp];
    ring.send(engine_.machine.events(), now, RingMessage{MessageKind::VoxelReply, station_, ring.position(StationKind::GraphicsProcessor, gp), bits, false},
              to, pack(Signal::Arrival, gp, block));
}

void HostAgent::handle_event(Tick now, std::uint64_t payload) {
    const auto gp = gp_of(payload);
    std::uint64_t task = kNoTask;
    if (next_task < engine_.job.tasks.size()) task = next_task++;
    RingNetwork& ring = engine_.machine.ring();
    ring.send(engine_.machine.events(), now, RingMessage{MessageKind::Command, engine_.host_station, ring.position(StationKind::GraphicsProcessor, gp), 32, false},
              *engine_.gps[gp], pack(Signal::Task, gp, task));
}

}  // namespace

RayCastReport time_ray_casting(Machine& machine, VoxelBlocks& blocks, const RayCastJob& job, const RayCastTimingOptions& options,
                               Tick start) {
    if (machine.gps().size() >= (1u << 22)) throw std::invalid_argument("ray cast timing: too many GPs");
    Engine engine(machine, blocks, job, options);
    engine.report.start = start;
    const auto requests_busy = [&machine] {
        Tick total = 0;
        for (const auto& r : machine.renderers()) total += static_cast<Tick>(r->request_busy_ps.value());
        return total;
    };
    const Tick renderer_busy_before = requests_busy();
    const auto ring_busy_before = static_cast<Tick>(machine.ring().busy_ps());

    if (options.assignment == RayAssignment::StaticTiles) {
        const std::size_t g = engine.gps.size();
        for (std::uint32_t t = 0; t < job.tasks.size(); ++t)
            engine.gps[static_cast<std::size_t>(job.tasks[t].tile) % g]->give_task(t);
    }
    for (auto& gp : engine.gps) gp->begin(start);

    EventQueue& events = machine.events();
    const std::uint64_t events_before = events.events_run();
    events.run_until(start + options.watchdog_limit);
    engine.report.events = events.events_run() - events_before;

    std::string stalled;
    for (const auto& gp : engine.gps)
        if (!gp->finished()) stalled += fmt::format(" {}", gp->describe_stall());
    if (!stalled.empty()) {
        const bool timed_out = !events.empty();
        events.clear();  // the agents handling them are about to go
        throw std::runtime_error(fmt::format("watchdog: {} at {:.6f} s simulated:{}",
                                             timed_out ? "the frame ran past the watchdog limit" : "the machine stalled with work left",
                                             ticks_to_seconds(events.now()), stalled));
    }
    engine.report.pass_end = engine.frame_buffer.pass_end;
    engine.report.end = start;
    for (const Tick t : engine.report.pass_end) engine.report.end = std::max(engine.report.end, t);
    engine.report.renderer_busy = requests_busy() - renderer_busy_before;
    engine.report.ring_busy = static_cast<Tick>(machine.ring().busy_ps()) - ring_busy_before;
    return engine.report;
}

}  // namespace pp5
