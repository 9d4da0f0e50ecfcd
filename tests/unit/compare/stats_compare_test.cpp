// Comparing two runs' statistics: numbers matched by path with their units, numbers in both ordered
// by relative change, those in one run only after them, the tolerance deciding what counts, and
// host timings left out unless asked for.

#include "frontends/compare/stats_compare.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pp5 {
namespace {

nlohmann::json run(double busy, double frame_seconds, int gps, double host) {
    nlohmann::json components = nlohmann::json::object();
    for (int g = 0; g < gps; ++g)
        components["gp[" + std::to_string(g) + "]"]["busy_time"] = {
            {"value", busy}, {"unit", "ps"}, {"description", "d"}};
    components["ring"]["latency"] = {{"unit", "ring cycles"},
                                     {"description", "d"},
                                     {"value", {{"bounds", {0, 1, 2}}, {"counts", {5, 1}}, {"sum", 7}}}};
    return {{"components", components},
            {"frames", {{{"simulated_seconds", frame_seconds}, {"host_seconds", host}, {"label", "front"}}}},
            {"summary", {{"simulated_seconds", {frame_seconds}}, {"host_seconds", host}}}};
}

TEST(StatsCompare, MatchesByPathWithUnitsAndOrdersByRelativeChange) {
    const StatsComparison c = compare_stats(run(100, 2.0, 2, 1.0), run(150, 1.0, 3, 9.0), {});
    ASSERT_FALSE(c.differences.empty());
    // gp busy +50%, frame time -50% (twice: the frame and the summary), then the third GP's, new.
    EXPECT_EQ(c.differences[0].path, "components/gp[0]/busy_time");
    EXPECT_EQ(c.differences[0].unit, "ps");
    EXPECT_DOUBLE_EQ(c.differences[0].relative(), 0.5);
    EXPECT_DOUBLE_EQ(c.differences[0].absolute(), 50.0);
    const auto find = [&](const std::string& path) {
        for (const StatDifference& d : c.differences)
            if (d.path == path) return d;
        ADD_FAILURE() << path << " not reported";
        return StatDifference{};
    };
    EXPECT_EQ(find("frames/0/simulated_seconds").unit, "s");
    EXPECT_EQ(find("summary/simulated_seconds/0").unit, "s");
    EXPECT_DOUBLE_EQ(find("frames/0/simulated_seconds").relative(), -0.5);
    const StatDifference& last = c.differences.back();
    EXPECT_EQ(last.path, "components/gp[2]/busy_time");
    EXPECT_FALSE(last.before);
    EXPECT_TRUE(std::isinf(last.relative()));
    for (const StatDifference& d : c.differences) EXPECT_EQ(d.path.find("host_seconds"), std::string::npos) << d.path;
    // The histogram's numbers are compared (and are equal here).
    EXPECT_GT(c.compared, 6u);
}

TEST(StatsCompare, ToleranceDecidesWhatIsBeyondItAndHostTimesCountOnlyWhenAsked) {
    const StatsComparison same = compare_stats(run(100, 2.0, 2, 1.0), run(100, 2.0, 2, 5.0), {});
    EXPECT_TRUE(same.differences.empty());
    EXPECT_EQ(same.beyond_tolerance, 0u);
    const StatsComparison host = compare_stats(run(100, 2.0, 2, 1.0), run(100, 2.0, 2, 5.0), {0.0, true});
    EXPECT_EQ(host.differences.size(), 2u);

    const StatsComparison small = compare_stats(run(100, 2.0, 2, 1.0), run(100.5, 2.0, 2, 1.0), {0.01});
    EXPECT_EQ(small.differences.size(), 2u);  // both GPs' busy time, by 0.5%
    EXPECT_EQ(small.beyond_tolerance, 0u);
    EXPECT_EQ(compare_stats(run(100, 2.0, 2, 1.0), run(100.5, 2.0, 2, 1.0), {0.001}).beyond_tolerance, 2u);
}

}  // namespace
}  // namespace pp5
