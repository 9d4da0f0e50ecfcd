#include "sim/core/event_queue.h"
#include "sim/core/clock_domain.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace pp5 {
namespace {

// Records the payloads it is handed, in the order the queue runs them.
struct EventRecorder final : EventHandler {
    std::vector<std::pair<Tick, std::uint64_t>> seen;
    void handle_event(Tick now, std::uint64_t payload) override { seen.emplace_back(now, payload); }
};

TEST(EventQueue, RunsInTimeOrder) {
    EventQueue q;
    EventRecorder r;
    q.schedule(300, r, 3);
    q.schedule(100, r, 1);
    q.schedule(200, r, 2);
    EXPECT_EQ(q.run_until(), 3u);
    ASSERT_EQ(r.seen.size(), 3u);
    EXPECT_EQ(r.seen[0], (std::pair<Tick, std::uint64_t>{100, 1}));
    EXPECT_EQ(r.seen[1], (std::pair<Tick, std::uint64_t>{200, 2}));
    EXPECT_EQ(r.seen[2], (std::pair<Tick, std::uint64_t>{300, 3}));
    EXPECT_EQ(q.now(), 300);
}

TEST(EventQueue, EqualTimesRunByPriorityThenInsertion) {
    EventQueue q;
    EventRecorder r;
    q.schedule(50, r, 10, /*priority=*/1);
    q.schedule(50, r, 11, 0);
    q.schedule(50, r, 12, 1);
    q.schedule(50, r, 13, 0);
    q.run_until();
    std::vector<std::uint64_t> order;
    for (const auto& [t, p] : r.seen) order.push_back(p);
    EXPECT_EQ(order, (std::vector<std::uint64_t>{11, 13, 10, 12}));
}

TEST(EventQueue, FirstInFirstOutOverManyTies) {
    EventQueue q;
    EventRecorder r;
    for (std::uint64_t i = 0; i < 1000; ++i) q.schedule(7, r, i);
    q.run_until();
    for (std::uint64_t i = 0; i < 1000; ++i) ASSERT_EQ(r.seen[i].second, i);
}

TEST(EventQueue, RunUntilStopsAtTheLimitAndResumes) {
    EventQueue q;
    EventRecorder r;
    q.schedule(10, r, 1);
    q.schedule(20, r, 2);
    q.schedule(30, r, 3);
    EXPECT_EQ(q.run_until(20), 2u);
    EXPECT_EQ(q.pending(), 1u);
    EXPECT_EQ(q.next_time(), 30);
    EXPECT_EQ(q.run_until(), 1u);
    EXPECT_TRUE(q.empty());
    EXPECT_EQ(q.events_run(), 3u);
}

// A handler that schedules follow-ups: the chain must interleave with other events by time.
struct Chain final : EventHandler {
    EventQueue& q;
    std::vector<Tick>& log;
    Chain(EventQueue& queue, std::vector<Tick>& l) : q(queue), log(l) {}
    void handle_event(Tick now, std::uint64_t remaining) override {
        log.push_back(now);
        if (remaining > 0) q.schedule_after(25, *this, remaining - 1);
    }
};

TEST(EventQueue, HandlersScheduleRelativeToNow) {
    EventQueue q;
    std::vector<Tick> log;
    Chain chain(q, log);
    q.schedule(0, chain, 3);
    q.run_until();
    EXPECT_EQ(log, (std::vector<Tick>{0, 25, 50, 75}));
}

TEST(EventQueue, RejectsEventsInThePast) {
    EventQueue q;
    EventRecorder r;
    q.schedule(100, r);
    q.run_until();
    EXPECT_THROW(q.schedule(99, r), std::logic_error);
}

TEST(ClockDomain, IntegerPeriodsFromMegahertz) {
    EXPECT_EQ(ClockDomain::from_megahertz("gp", 40.0).period(), 25'000);
    EXPECT_EQ(ClockDomain::from_megahertz("ring", 20.0).period(), 50'000);
    // 30 MHz is 33333.3 ps: the period rounds to whole picoseconds and the frequency reports it.
    const auto odd = ClockDomain::from_megahertz("odd", 30.0);
    EXPECT_EQ(odd.period(), 33'333);
    EXPECT_NEAR(odd.frequency_hz(), 30e6, 30e6 * 1e-4);
}

TEST(ClockDomain, CyclesAndEdges) {
    const ClockDomain clock("c", 25'000);
    EXPECT_EQ(clock.cycles_to_ticks(4), 100'000);
    EXPECT_EQ(clock.ticks_to_cycles(99'999), 3u);
    EXPECT_EQ(clock.next_edge(0), 0);
    EXPECT_EQ(clock.next_edge(1), 25'000);
    EXPECT_EQ(clock.next_edge(25'000), 25'000);
    EXPECT_THROW(ClockDomain("bad", 0), std::invalid_argument);
    EXPECT_THROW(ClockDomain::from_megahertz("bad", -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace pp5
