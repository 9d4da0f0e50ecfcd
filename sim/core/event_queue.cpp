#include "sim/core/event_queue.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pp5 {

void EventQueue::schedule(Tick when, EventHandler& handler, std::uint64_t payload, int priority) {
    if (when < now_)
        throw std::logic_error("event scheduled in the past: at " + std::to_string(when) + " ps, now " +
                               std::to_string(now_) + " ps");
    heap_.push_back(Event{when, priority, next_sequence_++, &handler, payload});
    std::push_heap(heap_.begin(), heap_.end(), RunsLater{});
}

bool EventQueue::step() {
    if (heap_.empty()) return false;
    std::pop_heap(heap_.begin(), heap_.end(), RunsLater{});
    const Event event = heap_.back();
    heap_.pop_back();
    now_ = event.when;
    ++events_run_;
    event.handler->handle_event(now_, event.payload);
    return true;
}

std::uint64_t EventQueue::run_until(Tick limit) {
    const std::uint64_t before = events_run_;
    while (!heap_.empty() && heap_.front().when <= limit) step();
    return events_run_ - before;
}

}  // namespace pp5
