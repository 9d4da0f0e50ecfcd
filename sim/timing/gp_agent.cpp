// A GP working through a GP phase's tasks: contexts, fetches, its cache, what it sends.
#include "sim/timing/engine_agents.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pp5::engine {

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
            ring.send(run_.machine.events(), t,
                      RingMessage{MessageKind::FetchRequest, station_, ring.position(StationKind::Renderer, r),
                                  static_cast<std::uint64_t>(count) * run_.phase.fetch_request_bits, false},
                      *run_.renderers[r], pack(Signal::Arrival, gp_.index(), kRefreshBatch - 1 - first));
            ++gp_.fetch_requests;
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
    // Round robin from the context after the last one run (the first context when none has run).
    const int n = static_cast<int>(contexts_.size());
    int c = last_context_;
    for (int i = 0; i < n; ++i) {
        c = c + 1 >= n ? 0 : c + 1;
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
            }
        }
        c.delivered = false;
        ++c.step;
    }
    c.active = false;
    ++gp_.items;
    if (--run_.remaining[c.task] == 0) return finish_task(c.task, t);
    return false;
}

void GpAgent::run(Tick now) {
    scheduled_ = false;
    if (idle_since_ >= 0) {
        const Tick waited = now - idle_since_;
        gp_.wait_ps += static_cast<std::uint64_t>(waited);
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
            }
            last_context_ = c;
            if (advance(c, t)) break;
        }
    }
    gp_.busy_ps += static_cast<std::uint64_t>(t - now);
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

}  // namespace pp5::engine
