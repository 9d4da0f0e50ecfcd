#include "ring/ring_network.h"
#include "sim/core/event_queue.h"
#include "sim/machine/machine.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pp5 {
namespace {

MachineConfig config_with(const std::vector<std::string>& overrides) {
    MachineConfig config = Machine::default_config();
    for (const auto& o : overrides) config.apply_override(o);
    return config;
}

struct Arrivals final : EventHandler {
    std::vector<std::pair<Tick, std::uint64_t>> seen;
    void handle_event(Tick now, std::uint64_t payload) override { seen.emplace_back(now, payload); }
};

TEST(RingNetwork, UnloadedMessageTakesHopsTimesLatencyPlusSizeOverWidth) {
    for (int hop_latency : {0, 1, 3}) {
        for (int header : {0, 2}) {
            RingNetwork ring(config_with({"ring.hop_latency_cycles=" + std::to_string(hop_latency),
                                          "ring.header_words=" + std::to_string(header)}),
                             4, 2);
            const std::size_t from = ring.position(StationKind::GraphicsProcessor, 1);
            const std::size_t to = ring.position(StationKind::Renderer, 0);
            const std::size_t hops = ring.hops(from, to);
            ASSERT_GT(hops, 0u);
            // 100 bits on a 32-bit channel: four words of payload.
            const RingTransit t = ring.transmit(0, RingMessage{MessageKind::FetchRequest, from, to, 100, false});
            const std::uint64_t cycles =
                hops * static_cast<std::uint64_t>(hop_latency) + static_cast<std::uint64_t>(header) + 4;
            EXPECT_EQ(t.start, 0);
            EXPECT_EQ(t.arrival, ring.clock().cycles_to_ticks(cycles))
                << "hop latency " << hop_latency << ", header " << header;
            EXPECT_EQ(t.hops, hops);
        }
    }
}

TEST(RingNetwork, SenderWaitsForTheNextRingClockEdge) {
    RingNetwork ring(config_with({"ring.header_words=0", "ring.hop_latency_cycles=0"}), 2, 2);
    const Tick period = ring.clock().period();
    const RingTransit t = ring.transmit(period / 3, RingMessage{MessageKind::Command, 0, 1, 32, false});
    EXPECT_EQ(t.start, period);
    EXPECT_EQ(t.arrival, 2 * period);
}

TEST(RingNetwork, WiderChannelsCarryAMessageInFewerWords) {
    RingNetwork narrow(config_with({"ring.header_words=1"}), 2, 2);
    RingNetwork wide(config_with({"ring.header_words=1", "ring.channel_width_bits=64"}), 2, 2);
    EXPECT_EQ(narrow.message_words(4000), 1u + 125u);
    EXPECT_EQ(wide.message_words(4000), 1u + 63u);
}

TEST(RingNetwork, SaturatedChannelCarriesItsBandwidthAndNoMore) {
    RingNetwork ring(config_with({"ring.channels=1", "ring.header_words=2", "ring.hop_latency_cycles=1"}), 4, 4);
    const std::size_t from = ring.position(StationKind::Renderer, 0);
    const std::size_t to = ring.position(StationKind::GraphicsProcessor, 0);
    const int messages = 1000;
    const std::uint64_t payload_bits = 125 * 32;
    RingTransit last;
    for (int i = 0; i < messages; ++i)
        last = ring.transmit(0, RingMessage{MessageKind::FetchReply, from, to, payload_bits, false});
    // Every message waits for all before it: the channel streams words back to back.
    const std::uint64_t words = ring.message_words(payload_bits);
    EXPECT_EQ(last.start, ring.clock().cycles_to_ticks(words * (messages - 1)));
    const Tick busy_until = last.start + ring.clock().cycles_to_ticks(words);
    const double carried_bits_per_second = static_cast<double>(words * messages * 32) / ticks_to_seconds(busy_until);
    EXPECT_DOUBLE_EQ(carried_bits_per_second, ring.bandwidth_bits_per_second());
    EXPECT_EQ(ring.horizon(), busy_until);
}

TEST(RingNetwork, MessagesSpreadOverChannelsThenQueue) {
    RingNetwork ring(config_with({"ring.channels=8", "ring.header_words=0", "ring.hop_latency_cycles=0"}), 8, 2);
    std::vector<RingTransit> sent;
    for (int i = 0; i < 16; ++i)
        sent.push_back(ring.transmit(0, RingMessage{MessageKind::PixelBlock, 1, 2, 10 * 32, false}));
    for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(sent[static_cast<std::size_t>(i)].channel, i);
        EXPECT_EQ(sent[static_cast<std::size_t>(i)].start, 0);
        EXPECT_EQ(sent[static_cast<std::size_t>(i + 8)].start, ring.clock().cycles_to_ticks(10));
    }
    const nlohmann::json stats = [&] {
        nlohmann::json out;
        ring.collect_stats(out);
        return out;
    }();
    EXPECT_EQ(stats["ring"]["messages"]["value"]["pixel_block"], 16);
    EXPECT_EQ(stats["ring"]["bytes"]["value"]["pixel_block"], 16 * 10 * 4);
    EXPECT_EQ(stats["ring"]["queueing_delay"]["value"]["samples"], 16);
    EXPECT_DOUBLE_EQ(stats["ring.channel[3]"]["utilisation"]["value"].get<double>(), 1.0);
}

TEST(RingNetwork, BroadcastPassesEveryOtherStation) {
    RingNetwork ring(config_with({"ring.header_words=0", "ring.hop_latency_cycles=2"}), 4, 4);
    const std::size_t n = ring.stations().size();
    const RingTransit t = ring.transmit(0, RingMessage{MessageKind::Broadcast, 3, 0, 32, true});
    EXPECT_EQ(t.hops, n - 1);
    EXPECT_EQ(t.arrival, ring.clock().cycles_to_ticks(2 * (n - 1) + 1));
}

TEST(RingNetwork, SendDeliversThePayloadAtTheArrivalTime) {
    RingNetwork ring(config_with({}), 2, 2);
    EventQueue events;
    Arrivals receiver;
    const RingTransit t = ring.send(events, 0, RingMessage{MessageKind::Command, 0, 3, 64, false}, receiver, 42);
    events.run_until();
    ASSERT_EQ(receiver.seen.size(), 1u);
    EXPECT_EQ(receiver.seen[0].first, t.arrival);
    EXPECT_EQ(receiver.seen[0].second, 42u);
}

TEST(RingNetwork, UnknownStationIsRefused) {
    RingNetwork ring(config_with({}), 2, 2);
    EXPECT_THROW(ring.transmit(0, RingMessage{MessageKind::Command, 0, 99, 32, false}), std::out_of_range);
}

}  // namespace
}  // namespace pp5
