#pragma once
// The ring network joining the host, the GPs, the renderers and the frame buffer: N channels of W bits
// at a clock f. Stations sit on the ring in a configurable order; a message travels downstream one hop
// per station it passes.
//
// Arbitration (documented policy, the physical one is not published): every channel carries one
// token. A sender takes the channel whose token is free earliest (the lowest-numbered on a tie) and
// holds it while it streams its message, header first, one word per ring cycle; the token is free again
// when the tail has left the sender. Senders are served in the order they ask (first come, first
// served). The token's own trip round the ring is not modelled. So:
//   start   = max(next ring clock edge after the request, the chosen channel's free time)
//   arrival = start + (hops x hop_latency + words) ring cycles,  words = header + ceil(payload / W)
// An unloaded message therefore takes hops x hop latency + size / width, and a saturated channel
// carries exactly W bits per ring cycle.

#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"
#include "sim/core/event_queue.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace pp5 {

enum class StationKind { Host, GraphicsProcessor, Renderer, FrameBuffer };
inline constexpr std::size_t kStationKindCount = 4;

struct RingStation {
    StationKind kind;
    std::size_t index;  // among stations of its kind
    std::string name;   // "gp[3]"
};

// What a message carries, for the statistics (bytes and messages by type) and traces: a GP asking a
// renderer for a block and the block coming back, primitives for a renderer's screen region, finished
// pixels for the frame buffer, data broadcast to every station, and commands.
enum class MessageKind : std::uint8_t { FetchRequest, FetchReply, PrimitiveBatch, PixelBlock, Broadcast, Command };
inline constexpr std::size_t kMessageKinds = 6;
const char* to_string(MessageKind kind);

struct RingMessage {
    MessageKind kind = MessageKind::Command;
    std::size_t from = 0;            // station position
    std::size_t to = 0;              // station position (ignored by a broadcast)
    std::uint64_t payload_bits = 0;  // rounded up to whole words
    bool broadcast = false;          // passes every other station; arrives when it reaches the last one
};

// When and how a message crossed the ring.
struct RingTransit {
    Tick requested = 0;  // the sender asked for a channel
    Tick start = 0;      // its head left the sender
    Tick arrival = 0;    // its tail reached the receiver
    int channel = 0;
    std::size_t hops = 0;
    std::uint64_t words = 0;  // header and payload
};

// Sees every message the ring carries (a trace writer, a test).
class RingObserver {
public:
    virtual ~RingObserver() = default;
    virtual void on_message(const RingMessage& message, const RingTransit& transit) = 0;
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
    int header_words() const { return header_words_; }
    int hop_latency_cycles() const { return hop_latency_cycles_; }
    const std::vector<RingStation>& stations() const { return stations_; }
    // Position of a station on the ring; throws std::out_of_range for an unknown one.
    std::size_t position(StationKind kind, std::size_t index) const;
    // Stations passed going downstream from `from` to `to` (the ring is one-way).
    std::size_t hops(std::size_t from_position, std::size_t to_position) const;
    double bandwidth_bits_per_second() const;  // all channels together
    // Words on the wire for a payload: the header plus the payload rounded up to whole words.
    std::uint64_t message_words(std::uint64_t payload_bits) const;

    // Takes a channel for `message`, asked for at `now`, and returns when it leaves and arrives.
    // Calls must come in non-decreasing `now` (the event queue's order): that order is the arbitration.
    RingTransit transmit(Tick now, const RingMessage& message);
    // transmit(), then hands `payload` to `receiver` at the arrival time.
    RingTransit send(EventQueue& events, Tick now, const RingMessage& message, EventHandler& receiver,
                     std::uint64_t payload, int priority = 0);

    void set_observer(RingObserver* observer) { observer_ = observer; }
    // Time the channels have been held, summed over channels.
    std::uint64_t busy_ps() const;
    // The last time any channel is held (utilisation is measured up to here).
    Tick horizon() const { return horizon_; }

private:
    ClockDomain clock_;
    int channel_width_bits_;
    int header_words_;
    int hop_latency_cycles_;
    std::vector<std::unique_ptr<RingChannel>> channels_;
    std::vector<Tick> channel_free_;
    std::vector<RingStation> stations_;
    // Each kind's stations' positions, by index: a message's destination is found without a search.
    std::array<std::vector<std::size_t>, kStationKindCount> positions_;
    RingObserver* observer_ = nullptr;
    Tick horizon_ = 0;

    VectorStat& messages_by_kind_;
    VectorStat& bytes_by_kind_;
    Histogram& queueing_delay_;
    Histogram& latency_;
};

}  // namespace pp5
