#pragma once
// The discrete-event core: a binary heap of small plain events over integer picoseconds.
//
// Ties are broken by (priority, insertion number): among events at the same time, a lower priority
// number runs first, and equal priorities run first-in first-out. The order of a run is therefore a
// function of what was scheduled, never of addresses or hash order, so every run is reproducible.
// Events carry a handler pointer and a 64-bit payload instead of a closure: no allocation per event.

#include "sim/core/time.h"

#include <cstdint>
#include <vector>

namespace pp5 {

class EventHandler {
public:
    virtual ~EventHandler() = default;
    virtual void handle_event(Tick now, std::uint64_t payload) = 0;
};

class EventQueue {
public:
    void schedule(Tick when, EventHandler& handler, std::uint64_t payload = 0, int priority = 0);
    void schedule_after(Tick delay, EventHandler& handler, std::uint64_t payload = 0, int priority = 0) {
        schedule(now_ + delay, handler, payload, priority);
    }

    // Run events in order until none is left or the next one lies beyond `limit`.
    // Returns the number of events run.
    std::uint64_t run_until(Tick limit = kMaxTick);
    // Run exactly one event if there is one; false when the queue is empty.
    bool step();
    // Drops every pending event (their handlers may be going away); time stays where it is.
    void clear() { heap_.clear(); }

    Tick now() const { return now_; }
    bool empty() const { return heap_.empty(); }
    std::size_t pending() const { return heap_.size(); }
    std::uint64_t events_run() const { return events_run_; }
    Tick next_time() const { return heap_.empty() ? kMaxTick : heap_.front().when; }

private:
    struct Event {
        Tick when;
        int priority;
        std::uint64_t sequence;
        EventHandler* handler;
        std::uint64_t payload;
    };
    // std heap functions build a max-heap, so "later" compares as "less urgent". A type of its own,
    // not a function pointer, so that every heap operation inlines it.
    struct RunsLater {
        bool operator()(const Event& a, const Event& b) const {
            if (a.when != b.when) return a.when > b.when;
            if (a.priority != b.priority) return a.priority > b.priority;
            return a.sequence > b.sequence;
        }
    };

    std::vector<Event> heap_;
    Tick now_ = 0;
    std::uint64_t next_sequence_ = 0;
    std::uint64_t events_run_ = 0;
};

}  // namespace pp5
