#include "ring/ring_network.h"

#include <algorithm>
#include <stdexcept>

namespace pp5 {

const ParamGroup& RingNetwork::params() {
    static const ParamGroup group = [] {
        ParamGroup g("ring", "The ring network joining every processor");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.integer("channels", 8, "count", 1, 256, "Independent channels (tokens) on the ring", Provenance::Default,
                  "machine.md: 8 x 32 bits x 20 MHz fits both Levoy's 640 Mb/s and Fuchs' 5 Gbit/s")
            .plausible(8, 8, "fixed by the sources: Fuchs' 5.12 Gbit/s over Levoy's 640 Mbit/s a channel")
            .integer("channel_width_bits", 32, "bits", 1, 1024, "Width of one channel", Provenance::Default,
                     "machine.md: 8 x 32 bits x 20 MHz, see ring.channels")
            .plausible(32, 32,
                       "with the clock, fixed by Levoy's 640 Mbit/s a channel; another split of that rate "
                       "changes only what ring.header_words and ring.hop_latency_cycles cover")
            .real("clock_mhz", 20.0, "MHz", 0.1, 10000, "Ring clock: one word per channel per cycle",
                  Provenance::Default, "machine.md: 8 x 32 bits x 20 MHz, see ring.channels")
            .plausible(20, 20, "with the width, fixed by Levoy's 640 Mbit/s a channel")
            .integer("hop_latency_cycles", 1, "cycles", 0, 1000, "Ring cycles for a word to pass one station",
                     Provenance::Default, "not published; machine.md guesses 1-2 ring clocks")
            .plausible(1, 4, "machine.md's 1-2 clocks, doubled for a station that buffers a word")
            .integer("header_words", 2, "words", 0, 64, "Header words that precede every message's payload",
                     Provenance::Default, "not published; machine.md guesses a few words")
            .plausible(1, 4, "a destination and a length at least; 'a few' at most")
            .text("station_order", "grouped", {"grouped", "interleaved"},
                  "Order of stations on the ring: grouped = host, all GPs, all renderers, frame buffer; "
                  "interleaved = GPs spread evenly between the renderers",
                  Provenance::Default, "the physical order is not published");
        return g;
    }();
    return group;
}

RingChannel::RingChannel(std::size_t index, Component* ring)
    : Component(indexed("channel", index), ring),
      messages(stats().counter("messages", "count", "Messages carried")),
      bytes(stats().counter("bytes", "bytes", "Header and payload bytes carried")),
      busy_ps(stats().counter("busy_time", "ps", "Simulated time the channel was held by a sender")) {}

const char* to_string(MessageKind kind) {
    switch (kind) {
        case MessageKind::FetchRequest: return "fetch_request";
        case MessageKind::FetchReply: return "fetch_reply";
        case MessageKind::PrimitiveBatch: return "primitive_batch";
        case MessageKind::PixelBlock: return "pixel_block";
        case MessageKind::Broadcast: return "broadcast";
        case MessageKind::Command: return "command";
    }
    return "unknown";
}

namespace {
std::vector<std::string> message_kind_names() {
    std::vector<std::string> names;
    for (std::size_t k = 0; k < kMessageKinds; ++k) names.emplace_back(to_string(static_cast<MessageKind>(k)));
    return names;
}
// Powers of two of ring cycles, 0 to 2^20: a delay histogram readable at any load.
std::vector<std::int64_t> cycle_buckets() {
    std::vector<std::int64_t> bounds{0};
    for (std::int64_t b = 1; b <= (1 << 20); b *= 2) bounds.push_back(b);
    return bounds;
}
}  // namespace

RingNetwork::RingNetwork(const MachineConfig& config, std::size_t gps, std::size_t renderers)
    : Component("ring", nullptr),
      clock_(ClockDomain::from_megahertz("ring.clock", config.real("ring.clock_mhz"))),
      channel_width_bits_(static_cast<int>(config.integer("ring.channel_width_bits"))),
      header_words_(static_cast<int>(config.integer("ring.header_words"))),
      hop_latency_cycles_(static_cast<int>(config.integer("ring.hop_latency_cycles"))),
      messages_by_kind_(stats().vector("messages", "count", "Messages carried, by type", message_kind_names())),
      bytes_by_kind_(
          stats().vector("bytes", "bytes", "Header and payload bytes carried, by type", message_kind_names())),
      queueing_delay_(stats().histogram("queueing_delay", "ring cycles",
                                        "Wait from asking for a channel to the message's head leaving",
                                        cycle_buckets())),
      latency_(stats().histogram("latency", "ring cycles", "From asking for a channel to the tail's arrival",
                                 cycle_buckets())) {
    const auto channel_count = static_cast<std::size_t>(config.integer("ring.channels"));
    for (std::size_t i = 0; i < channel_count; ++i) {
        channels_.push_back(std::make_unique<RingChannel>(i, this));
        RingChannel* channel = channels_.back().get();
        channel->stats().formula(
            "utilisation", "fraction", "Busy time over the time up to the ring's last activity", [this, channel] {
                return horizon_ > 0 ? static_cast<double>(channel->busy_ps.value()) / static_cast<double>(horizon_)
                                    : 0.0;
            });
    }
    channel_free_.assign(channel_count, 0);

    const auto add = [this](StationKind kind, std::size_t index, const char* base) {
        stations_.push_back(RingStation{kind, index, indexed(base, index)});
    };
    stations_.push_back(RingStation{StationKind::Host, 0, "host"});
    if (config.text("ring.station_order") == "grouped") {
        for (std::size_t i = 0; i < gps; ++i) add(StationKind::GraphicsProcessor, i, "gp");
        for (std::size_t i = 0; i < renderers; ++i) add(StationKind::Renderer, i, "renderer");
    } else {
        // Spread the GPs evenly: after renderer r come the GPs whose share of the ring falls there.
        std::size_t next_gp = 0;
        for (std::size_t r = 0; r < renderers; ++r) {
            add(StationKind::Renderer, r, "renderer");
            const std::size_t until = renderers == 0 ? gps : (r + 1) * gps / renderers;
            for (; next_gp < until; ++next_gp) add(StationKind::GraphicsProcessor, next_gp, "gp");
        }
        for (; next_gp < gps; ++next_gp) add(StationKind::GraphicsProcessor, next_gp, "gp");
    }
    stations_.push_back(RingStation{StationKind::FrameBuffer, 0, "frame_buffer"});
    for (std::size_t p = 0; p < stations_.size(); ++p) {
        std::vector<std::size_t>& of_kind = positions_[static_cast<std::size_t>(stations_[p].kind)];
        if (of_kind.size() <= stations_[p].index) of_kind.resize(stations_[p].index + 1);
        of_kind[stations_[p].index] = p;
    }

    stats().formula("stations", "count", "Stations on the ring",
                    [this] { return static_cast<double>(stations_.size()); });
    stats().formula("peak_bandwidth", "bit/s", "All channels together, one word per channel per ring cycle",
                    [this] { return bandwidth_bits_per_second(); });
}

std::size_t RingNetwork::position(StationKind kind, std::size_t index) const {
    const std::vector<std::size_t>& of_kind = positions_[static_cast<std::size_t>(kind)];
    if (index >= of_kind.size()) throw std::out_of_range("no such ring station");
    return of_kind[index];
}

std::size_t RingNetwork::hops(std::size_t from_position, std::size_t to_position) const {
    const std::size_t n = stations_.size();
    return (to_position + n - from_position) % n;
}

std::uint64_t RingNetwork::message_words(std::uint64_t payload_bits) const {
    const auto width = static_cast<std::uint64_t>(channel_width_bits_);
    return static_cast<std::uint64_t>(header_words_) + (payload_bits + width - 1) / width;
}

RingTransit RingNetwork::transmit(Tick now, const RingMessage& message) {
    const std::size_t n = stations_.size();
    if (message.from >= n || (!message.broadcast && message.to >= n))
        throw std::out_of_range("ring message between unknown stations");
    RingTransit transit;
    transit.requested = now;
    transit.words = message_words(message.payload_bits);
    transit.hops = message.broadcast ? n - 1 : hops(message.from, message.to);
    const auto earliest = std::min_element(channel_free_.begin(), channel_free_.end());
    transit.channel = static_cast<int>(earliest - channel_free_.begin());
    transit.start = std::max(clock_.next_edge(now), *earliest);
    const Tick hold = clock_.cycles_to_ticks(transit.words);
    *earliest = transit.start + hold;
    transit.arrival =
        transit.start + hold + clock_.cycles_to_ticks(transit.hops * static_cast<std::uint64_t>(hop_latency_cycles_));
    horizon_ = std::max(horizon_, *earliest);

    RingChannel& channel = *channels_[static_cast<std::size_t>(transit.channel)];
    const std::uint64_t bytes = transit.words * static_cast<std::uint64_t>(channel_width_bits_) / 8;
    ++channel.messages;
    channel.bytes += bytes;
    channel.busy_ps += static_cast<std::uint64_t>(hold);
    const auto kind = static_cast<std::size_t>(message.kind);
    messages_by_kind_.add(kind);
    bytes_by_kind_.add(kind, bytes);
    queueing_delay_.sample(static_cast<std::int64_t>(clock_.ticks_to_cycles(transit.start - now)));
    latency_.sample(static_cast<std::int64_t>(clock_.ticks_to_cycles(transit.arrival - now)));
    if (observer_ != nullptr) observer_->on_message(message, transit);
    return transit;
}

RingTransit RingNetwork::send(EventQueue& events, Tick now, const RingMessage& message, EventHandler& receiver,
                              std::uint64_t payload, int priority) {
    const RingTransit transit = transmit(now, message);
    events.schedule(transit.arrival, receiver, payload, priority);
    return transit;
}

std::uint64_t RingNetwork::busy_ps() const {
    std::uint64_t total = 0;
    for (const auto& channel : channels_) total += channel->busy_ps.value();
    return total;
}

double RingNetwork::bandwidth_bits_per_second() const {
    return static_cast<double>(channels_.size()) * channel_width_bits_ * clock_.frequency_hz();
}

}  // namespace pp5
