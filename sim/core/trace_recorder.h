#pragma once
// A window of the timing layer's activity as Chrome trace-event JSON, which Perfetto and
// chrome://tracing open: one track per GP, renderer and ring channel, slices for what each did
// (computing, waiting, PP passes, answering requests, messages on the wire), and arrows for messages
// from sender to receiver. An observer only: recording changes nothing in the simulation. Off unless
// asked for, limited to a window of simulated time and a number of events.

#include "sim/core/time.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace pp5 {

class TraceRecorder {
public:
    TraceRecorder(Tick window_start, Tick window_end, std::size_t max_events);

    // A track (a row in the viewer) by name, grouped under `group` ("GPs", "renderers", "ring").
    int track(const std::string& group, const std::string& name);
    void slice(int track, const std::string& name, Tick start, Tick end);
    // An arrow from one track at `from` to another at `to`.
    void flow(int from_track, Tick from, int to_track, Tick to, const std::string& name);

    // Also keep every slice's span by track group ("GPs", "renderers", "ring"), whatever the window and
    // the event limit: what a utilisation-over-time plot is drawn from. A "waiting" slice is idle time.
    void keep_busy_spans(bool keep) { keep_busy_ = keep; }
    const std::map<std::string, std::vector<std::pair<Tick, Tick>>>& busy_spans() const { return busy_; }

    // Also keep up to `max` slices themselves (which track, what it did, when), whatever the window and
    // the event limit: what a picture of one frame's timeline is drawn from. forget_slices() starts
    // the list again (a session does as each frame's timing begins).
    struct Slice {
        int track;  // as track() returned it
        int what;   // index into slice_names()
        Tick start;
        Tick end;
    };
    void keep_slices(std::size_t max) { max_slices_ = max; }
    void forget_slices();
    const std::vector<Slice>& slices() const { return slices_; }
    const std::vector<std::string>& slice_names() const { return slice_names_; }
    // Slices past `max` since the list started again.
    std::size_t slices_dropped() const { return slices_dropped_; }
    // Every track, in the order they were made, with the group and name each was made with.
    struct Track {
        int id;  // as track() returned it
        std::string group;
        std::string name;
    };
    const std::vector<Track>& tracks() const { return track_list_; }
    // Whether the trace-event document records anything: a recorder kept only for its spans or slices
    // has no window, and its callers can skip the work of describing events (the message arrows).
    bool records_events() const { return max_events_ > 0 && window_end_ > window_start_; }

    bool full() const { return events_ >= max_events_; }
    std::size_t events() const { return events_; }
    std::size_t dropped() const { return dropped_; }
    // The whole document: {"traceEvents": [...], ...}.
    std::string to_text() const;

private:
    bool in_window(Tick start, Tick end) const { return end >= window_start_ && start <= window_end_; }
    bool take();
    void keep_slice(int track, const std::string& name, Tick start, Tick end);

    Tick window_start_;
    Tick window_end_;
    std::size_t max_events_;
    std::size_t events_ = 0;
    std::size_t dropped_ = 0;
    std::uint64_t next_flow_ = 1;
    std::map<std::string, int> groups_;
    std::map<std::pair<int, std::string>, int> tracks_;
    std::vector<std::string> records_;      // serialised events, in the order recorded
    std::vector<std::string> group_names_;  // by group number - 1
    bool keep_busy_ = false;
    std::map<std::string, std::vector<std::pair<Tick, Tick>>> busy_;
    std::vector<Track> track_list_;
    std::size_t max_slices_ = 0;
    std::size_t slices_dropped_ = 0;
    std::vector<Slice> slices_;
    std::vector<std::string> slice_names_;
    std::map<std::string, int, std::less<>> slice_name_index_;
};

}  // namespace pp5
