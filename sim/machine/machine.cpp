#include "sim/machine/machine.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace pp5 {

std::vector<const ParamGroup*> Machine::param_groups() {
    return {&GraphicsProcessor::params(), &GpCostModel::params(), &Renderer::params(), &PpCostModel::params(), &FrameBuffer::params(),
            &RingNetwork::params()};
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

Machine::Machine(const MachineConfig& config)
    : config_(config),
      frame_buffer_(config_),
      gps_(build_all<GraphicsProcessor>(config_.integer("gp.count"), config_)),
      renderers_(build_all<Renderer>(config_.integer("renderer.count"), config_)),
      ring_(config_, gps_.size(), renderers_.size()) {}

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
