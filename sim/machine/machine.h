#pragma once
// The machine: every component of a Pixel-planes 5 built from a resolved configuration, the event
// queue they share, and the statistics of all of them. Adding a kind of component means declaring its
// ParamGroup, listing it in param_groups(), and building its instances in the constructor.

#include "ring/ring_network.h"
#include "sim/components/frame_buffer.h"
#include "sim/components/graphics_processor.h"
#include "sim/components/renderer.h"
#include "sim/core/config.h"
#include "sim/core/event_queue.h"
#include "sim/core/trace_recorder.h"

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace pp5 {

// The machine's shape as its components were built: what a kernel lays its data out by, read here
// once rather than by key in every kernel.
struct MachineShape {
    int gps = 0;
    std::uint64_t gp_memory_bytes = 0;
    int renderers = 0;
    int pp_columns = 0, pp_rows = 0;  // each renderer's PP array
    int local_memory_bits = 0;        // per PP
    int backing_store_bits = 0;       // per PP
    int pps_per_renderer() const { return pp_columns * pp_rows; }
};

class Machine {
public:
    // Every parameter group of every kind of component, in the order `pp5sim params` lists them.
    static std::vector<const ParamGroup*> param_groups();
    // A configuration holding every group's defaults.
    static MachineConfig default_config();

    explicit Machine(const MachineConfig& config);

    const MachineConfig& config() const { return config_; }
    const MachineShape& shape() const { return shape_; }
    EventQueue& events() { return events_; }
    const EventQueue& events() const { return events_; }
    Host& host() { return host_; }
    FrameBuffer& frame_buffer() { return frame_buffer_; }
    const FrameBuffer& frame_buffer() const { return frame_buffer_; }
    RingNetwork& ring() { return ring_; }
    const RingNetwork& ring() const { return ring_; }
    std::vector<std::unique_ptr<GraphicsProcessor>>& gps() { return gps_; }
    const std::vector<std::unique_ptr<GraphicsProcessor>>& gps() const { return gps_; }
    std::vector<std::unique_ptr<Renderer>>& renderers() { return renderers_; }
    const std::vector<std::unique_ptr<Renderer>>& renderers() const { return renderers_; }

    // Records the run into `trace` from now on (nullptr stops): renderers' passes and requests, ring
    // messages; the kernels' timing layers record the GPs through trace(). The recorder must outlive
    // the recording.
    void attach_trace(TraceRecorder* trace);
    TraceRecorder* trace() const { return trace_; }
    // The trace track of a ring station ("gp[3]", "renderer[1]", "host", "frame_buffer").
    int trace_track(std::size_t station) const;
    // The (group, name) of every track this machine's components record on: its stations, then its
    // ring channels. A recorder that outlives one machine keeps the others' tracks as well.
    std::vector<std::pair<std::string, std::string>> trace_track_names() const;

    // Every top-level component (children are reached through them).
    std::vector<const Component*> components() const;
    // {"gp[0]": {...}, "ring.channel[3]": {...}, ...}
    nlohmann::json statistics() const;
    // A few lines describing the assembled machine.
    std::string summary() const;

private:
    MachineConfig config_;
    MachineShape shape_;
    EventQueue events_;
    Host host_;
    FrameBuffer frame_buffer_;
    std::vector<std::unique_ptr<GraphicsProcessor>> gps_;
    std::vector<std::unique_ptr<Renderer>> renderers_;
    RingNetwork ring_;
    TraceRecorder* trace_ = nullptr;
    std::unique_ptr<RingObserver> ring_tracer_;
};

}  // namespace pp5
