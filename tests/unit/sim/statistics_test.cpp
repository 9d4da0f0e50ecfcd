#include "sim/core/statistics.h"
#include "sim/core/component.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace pp5 {
namespace {

TEST(Statistics, CounterVectorAndFormula) {
    StatGroup group;
    Counter& hits = group.counter("hits", "count", "Cache hits");
    Counter& misses = group.counter("misses", "count", "Cache misses");
    group.formula("hit_rate", "ratio", "hits / accesses", [&] {
        return static_cast<double>(hits.value()) / static_cast<double>(hits.value() + misses.value());
    });
    VectorStat& bytes = group.vector("bytes", "bytes", "By type", {"request", "reply"});
    hits += 3;
    ++misses;
    bytes.add(1, 64);
    bytes.add(0, 8);

    const nlohmann::json j = group.to_json();
    EXPECT_EQ(j["hits"]["value"], 3);
    EXPECT_EQ(j["hits"]["unit"], "count");
    EXPECT_EQ(j["hits"]["description"], "Cache hits");
    EXPECT_DOUBLE_EQ(j["hit_rate"]["value"].get<double>(), 0.75);
    EXPECT_EQ(j["bytes"]["value"]["reply"], 64);
    EXPECT_EQ(bytes.total(), 72u);

    group.reset();
    EXPECT_EQ(hits.value(), 0u);
    EXPECT_EQ(bytes.total(), 0u);
    EXPECT_TRUE(group.to_json()["hit_rate"]["value"].is_null());  // 0/0 is written as null, not NaN
}

TEST(Statistics, HistogramBuckets) {
    StatGroup group;
    Histogram& h = group.histogram("delay", "ps", "Queueing delay", {0, 10, 100, 1000});
    h.sample(-1);
    h.sample(0);
    h.sample(9);
    h.sample(10, 2);
    h.sample(999);
    h.sample(1000);
    EXPECT_EQ(h.underflow(), 1u);
    EXPECT_EQ(h.bucket(0), 2u);
    EXPECT_EQ(h.bucket(1), 2u);
    EXPECT_EQ(h.bucket(2), 1u);
    EXPECT_EQ(h.overflow(), 1u);
    EXPECT_EQ(h.samples(), 7u);
    EXPECT_EQ(h.sum(), -1 + 0 + 9 + 20 + 999 + 1000);
}

TEST(Statistics, DuplicateNamesAreAProgrammingError) {
    StatGroup group;
    group.counter("x", "count", "");
    EXPECT_THROW(group.counter("x", "count", ""), std::logic_error);
    EXPECT_THROW(group.histogram("h", "", "", {5}), std::logic_error);
}

TEST(Component, HierarchicalNamesAndStatistics) {
    Component ring("ring", nullptr);
    Component channel(Component::indexed("channel", 2), &ring);
    channel.stats().counter("messages", "count", "Messages") += 5;
    EXPECT_EQ(channel.name(), "ring.channel[2]");
    nlohmann::json all = nlohmann::json::object();
    ring.collect_stats(all);
    EXPECT_EQ(all["ring.channel[2]"]["messages"]["value"], 5);
    EXPECT_FALSE(all.contains("ring"));  // no statistics of its own
    ring.reset_stats();
    EXPECT_EQ(dynamic_cast<const Counter*>(channel.stats().find("messages"))->value(), 0u);
}

}  // namespace
}  // namespace pp5
