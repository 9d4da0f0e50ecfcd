#pragma once
// The ring network joining the host, the GPs, the renderers and the frame buffer: N channels of W bits
// at a clock f. Stations sit on the ring in a configurable order; a message travels one hop per
// station it passes. Arbitration and contention arrive with the ray-caster work; here the ring declares
// its parameters, its stations and per-channel statistics, and answers closed-form questions.

#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"

#include <string>
#include <vector>

namespace pp5 {

enum class StationKind { Host, GraphicsProcessor, Renderer, FrameBuffer };

struct RingStation {
    StationKind kind;
    std::size_t index;  // among stations of its kind
    std::string name;   // "gp[3]"
};

class RingChannel : public Component {
public:
    RingChannel(std::size_t index, Component* ring);

    Counter& messages;
    Counter& bytes;
    Counter& busy_ps;
};

class RingNetwork : public Component {
public:
    static const ParamGroup& params();

    RingNetwork(const MachineConfig& config, std::size_t gps, std::size_t renderers);

    const ClockDomain& clock() const { return clock_; }
    int channel_count() const { return static_cast<int>(channels_.size()); }
    int channel_width_bits() const { return channel_width_bits_; }
    const std::vector<RingStation>& stations() const { return stations_; }
    // Position of a station on the ring; throws std::out_of_range for an unknown one.
    std::size_t position(StationKind kind, std::size_t index) const;
    // Stations passed going downstream from `from` to `to` (the ring is one-way).
    std::size_t hops(std::size_t from_position, std::size_t to_position) const;
    double bandwidth_bits_per_second() const;  // all channels together

private:
    ClockDomain clock_;
    int channel_width_bits_;
    std::vector<std::unique_ptr<RingChannel>> channels_;
    std::vector<RingStation> stations_;
};

}  // namespace pp5
