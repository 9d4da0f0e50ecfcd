#include "sim/core/work_progress.h"

namespace pp5 {

namespace {
thread_local WorkListener* current_listener = nullptr;
}  // namespace

void report_work(std::string_view stage, std::size_t done, std::size_t total) {
    if (current_listener) current_listener->on_work(stage, done, total);
}

ScopedWorkListener::ScopedWorkListener(WorkListener& listener) : previous_(current_listener) {
    current_listener = &listener;
}

ScopedWorkListener::~ScopedWorkListener() { current_listener = previous_; }

}  // namespace pp5
