#include "sim/core/trace_recorder.h"

#include <nlohmann/json.hpp>

namespace pp5 {

namespace {
double microseconds(Tick t) { return static_cast<double>(t) / 1e6; }
}  // namespace

TraceRecorder::TraceRecorder(Tick window_start, Tick window_end, std::size_t max_events)
    : window_start_(window_start), window_end_(window_end), max_events_(max_events) {}

int TraceRecorder::track(const std::string& group, const std::string& name) {
    auto [g, new_group] = groups_.try_emplace(group, static_cast<int>(groups_.size()) + 1);
    const int pid = g->second;
    if (new_group) {
        group_names_.push_back(group);
        records_.push_back(
            nlohmann::json{{"ph", "M"}, {"name", "process_name"}, {"pid", pid}, {"args", {{"name", group}}}}.dump());
    }
    auto [t, new_track] = tracks_.try_emplace({pid, name}, static_cast<int>(tracks_.size()) + 1);
    if (new_track) {
        track_list_.push_back({pid * 100000 + t->second, group, name});
        records_.push_back(nlohmann::json{
            {"ph", "M"}, {"name", "thread_name"}, {"pid", pid}, {"tid", t->second}, {"args", {{"name", name}}}}
                               .dump());
    }
    return pid * 100000 + t->second;
}

bool TraceRecorder::take() {
    if (events_ >= max_events_) {
        ++dropped_;
        return false;
    }
    ++events_;
    return true;
}

void TraceRecorder::keep_slice(int track, const std::string& name, Tick start, Tick end) {
    if (slices_.size() >= max_slices_) {
        ++slices_dropped_;
        return;
    }
    auto [at, added] = slice_name_index_.try_emplace(name, static_cast<int>(slice_names_.size()));
    if (added) slice_names_.push_back(name);
    slices_.push_back({track, at->second, start, end});
}

void TraceRecorder::forget_slices() {
    slices_.clear();
    slices_dropped_ = 0;
}

void TraceRecorder::slice(int track, const std::string& name, Tick start, Tick end) {
    if (keep_busy_ && name != "waiting" && end > start) {
        const auto group = static_cast<std::size_t>(track / 100000);
        if (group >= 1 && group <= group_names_.size()) busy_[group_names_[group - 1]].emplace_back(start, end);
    }
    if (max_slices_ > 0) keep_slice(track, name, start, end);
    if (!in_window(start, end) || !take()) return;
    records_.push_back(nlohmann::json{{"ph", "X"},
                                      {"name", name},
                                      {"pid", track / 100000},
                                      {"tid", track % 100000},
                                      {"ts", microseconds(start)},
                                      {"dur", microseconds(end - start)}}
                           .dump());
}

void TraceRecorder::flow(int from_track, Tick from, int to_track, Tick to, const std::string& name) {
    if (!in_window(from, to) || !take()) return;
    const std::uint64_t id = next_flow_++;
    records_.push_back(nlohmann::json{{"ph", "s"},
                                      {"id", id},
                                      {"name", name},
                                      {"cat", "message"},
                                      {"pid", from_track / 100000},
                                      {"tid", from_track % 100000},
                                      {"ts", microseconds(from)}}
                           .dump());
    records_.push_back(nlohmann::json{
        {"ph", "f"},
        {"bp", "e"},
        {"id", id},
        {"name", name},
        {"cat", "message"},
        {"pid", to_track / 100000},
        {"tid", to_track % 100000},
        {"ts",
         microseconds(to)}}.dump());
}

std::string TraceRecorder::to_text() const {
    std::string text = "{\"traceEvents\": [\n";
    for (std::size_t i = 0; i < records_.size(); ++i) {
        text += records_[i];
        text += i + 1 < records_.size() ? ",\n" : "\n";
    }
    const nlohmann::json other = {{"source", "pp5sim"},
                                  {"window_us", {microseconds(window_start_), microseconds(window_end_)}},
                                  {"events", events_},
                                  {"dropped_after_limit", dropped_}};
    text += "], \"displayTimeUnit\": \"ns\", \"otherData\": " + other.dump() + "}\n";
    return text;
}

}  // namespace pp5
