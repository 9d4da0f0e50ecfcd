#include "sim/machine/machine.h"

#include "sim/core/calibration.h"
#include "sim/core/host_memory.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace pp5 {

std::vector<const ParamGroup*> Machine::param_groups() {
    return {&GraphicsProcessor::params(), &GpCostModel::params(), &Renderer::params(),         &PpCostModel::params(),
            &FrameBuffer::params(),       &RingNetwork::params(), &CalibrationScales::params()};
}

MachineConfig Machine::default_config() { return MachineConfig(param_groups()); }

namespace {
template <class T>
std::vector<std::unique_ptr<T>> build_all(std::int64_t count, const MachineConfig& config) {
    std::vector<std::unique_ptr<T>> all;
    for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) all.push_back(std::make_unique<T>(i, config));
    return all;
}
}  // namespace

namespace {

// The renderers' backing stores are the machine's one large allocation; refused before it is made. Only
// the pages a kernel writes become resident, but a kernel may write all of them.
const MachineConfig& fits_host(const MachineConfig& config) {
    const double pps = static_cast<double>(config.integer("renderer.pp_columns")) *
                       static_cast<double>(config.integer("renderer.pp_rows"));
    const double words = static_cast<double>((config.integer("renderer.backing_store_bits") + 63) / 64);
    const double bytes = static_cast<double>(config.integer("renderer.count")) * pps * words * 8;
    check_fits_host_memory(
        config.describe_origin("renderer.count"), "renderer.count", bytes,
        fmt::format("simulating {} renderers of {} PPs with {} bits of backing store each",
                    config.integer("renderer.count"), pps, config.integer("renderer.backing_store_bits")));
    return config;
}

}  // namespace

// A component that refuses its parameters is named with where the value came from.
Machine::Machine(const MachineConfig& config) try
    : config_(fits_host(config)),
      frame_buffer_(config_),
      gps_(build_all<GraphicsProcessor>(config_.integer("gp.count"), config_)),
      renderers_(build_all<Renderer>(config_.integer("renderer.count"), config_)),
      ring_(config_, gps_.size(), renderers_.size()) {
    shape_.gps = static_cast<int>(gps_.size());
    shape_.gp_memory_bytes = static_cast<std::uint64_t>(config_.integer("gp.memory_bytes"));
    shape_.renderers = static_cast<int>(renderers_.size());
    shape_.pp_columns = static_cast<int>(config_.integer("renderer.pp_columns"));
    shape_.pp_rows = static_cast<int>(config_.integer("renderer.pp_rows"));
    shape_.local_memory_bits = static_cast<int>(config_.integer("renderer.local_memory_bits"));
    shape_.backing_store_bits = static_cast<int>(config_.integer("renderer.backing_store_bits"));
} catch (const InputError& error) {
    throw config.naming_origin(error);
}

namespace {
const char* const kRingTraceGroup = "ring";
std::string ring_channel_track(int channel) { return Component::indexed("channel", static_cast<std::size_t>(channel)); }

// Draws each ring message as a slice on its channel's track and an arrow from sender to receiver.
class RingTracer final : public RingObserver {
public:
    RingTracer(Machine& machine, TraceRecorder& trace) : machine_(machine), trace_(trace) {
        for (int c = 0; c < machine.ring().channel_count(); ++c)
            channels_.push_back(trace.track(kRingTraceGroup, ring_channel_track(c)));
    }
    void on_message(const RingMessage& message, const RingTransit& transit) override {
        const RingNetwork& ring = machine_.ring();
        const Tick hold = ring.clock().cycles_to_ticks(transit.words);
        trace_.slice(channels_[static_cast<std::size_t>(transit.channel)], to_string(message.kind), transit.start,
                     transit.start + hold);
        // The arrows exist only in the trace-event document; a recorder kept for spans has none.
        if (!message.broadcast && trace_.records_events())
            trace_.flow(machine_.trace_track(message.from), transit.requested, machine_.trace_track(message.to),
                        transit.arrival, to_string(message.kind));
    }

private:
    Machine& machine_;
    TraceRecorder& trace_;
    std::vector<int> channels_;
};
}  // namespace

void Machine::attach_trace(TraceRecorder* trace) {
    trace_ = trace;
    for (auto& r : renderers_) r->set_trace(trace);
    ring_tracer_ = trace != nullptr ? std::make_unique<RingTracer>(*this, *trace) : nullptr;
    ring_.set_observer(ring_tracer_.get());
}

namespace {
// The group of trace tracks a ring station's records go under.
const char* trace_group(StationKind kind) {
    switch (kind) {
        case StationKind::GraphicsProcessor: return "GPs";
        case StationKind::Renderer: return "renderers";
        case StationKind::Host:
        case StationKind::FrameBuffer: break;
    }
    return "host and frame buffer";
}
}  // namespace

int Machine::trace_track(std::size_t station) const {
    const RingStation& s = ring_.stations().at(station);
    return trace_->track(trace_group(s.kind), s.name);
}

std::vector<std::pair<std::string, std::string>> Machine::trace_track_names() const {
    std::vector<std::pair<std::string, std::string>> names;
    for (const RingStation& s : ring_.stations()) names.emplace_back(trace_group(s.kind), s.name);
    for (int c = 0; c < ring_.channel_count(); ++c) names.emplace_back(kRingTraceGroup, ring_channel_track(c));
    return names;
}

std::vector<const Component*> Machine::components() const {
    std::vector<const Component*> all{&host_};
    for (const auto& gp : gps_) all.push_back(gp.get());
    for (const auto& r : renderers_) all.push_back(r.get());
    all.push_back(&ring_);
    all.push_back(&frame_buffer_);
    return all;
}

nlohmann::json Machine::statistics() const {
    nlohmann::json out = nlohmann::json::object();
    for (const Component* c : components()) c->collect_stats(out);
    return out;
}

std::string Machine::summary() const {
    const auto& r = *renderers_.front();
    const std::uint64_t pps = r.pixel_processors() * renderers_.size();
    return fmt::format(
        "machine {}: {} GPs at {:.0f} MHz, {} renderers of {} PPs ({} PPs, {} + {} bits each), "
        "ring {} x {} bits at {:.0f} MHz ({:.0f} Mbit/s), frame buffer {}x{}",
        config_.machine_name(), gps_.size(), gps_.front()->clock().frequency_hz() / 1e6, renderers_.size(),
        r.pixel_processors(), pps, r.local_memory_bits(), r.backing_store_bits(), ring_.channel_count(),
        ring_.channel_width_bits(), ring_.clock().frequency_hz() / 1e6, ring_.bandwidth_bits_per_second() / 1e6,
        frame_buffer_.width(), frame_buffer_.height());
}

}  // namespace pp5
