// Uncertainty from the documented guesses' plausible ranges: every guess has a range with a reason,
// the band of a figure whose response is known is the one the rectangular distributions give, and
// on a real recording the linearised band holds the figures of machines drawn from the ranges.

#include "calibration/uncertainty.h"
#include "calibration/timing_model.h"
#include "calibration_support.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace pp5 {
namespace {

TEST(Uncertainty, EveryTimingGuessHasAPlausibleRangeWithAReason) {
    const MachineConfig config(run_param_groups());
    std::size_t guesses = 0;
    for (const ParamGroup* group : config.groups()) {
        for (const ParamSpec& spec : group->specs()) {
            const std::string key = group->prefix() + "." + spec.name;
            if (spec.type != ParamType::Integer && spec.type != ParamType::Real) continue;
            if (!is_timing_parameter(key) || key.starts_with("calibration.") || spec.provenance != Provenance::Default)
                continue;
            ++guesses;
            ASSERT_TRUE(spec.plausible.has_value()) << key << " is a guess without a plausible range";
            EXPECT_FALSE(spec.plausible->why.empty()) << key;
        }
    }
    EXPECT_GT(guesses, 50u);  // the machine's own and every kernel's cost tables
}

TEST(Uncertainty, ARangeDeclaredAroundTheDefaultMovesWithAnotherMachinesValue) {
    MachineConfig config(run_param_groups());
    config.set("gp_cost.cache_lookup_cycles", 30.0, "test");  // the default is 10, plausibly 5 to 20
    const std::vector<UncertainParameter> found = uncertain_parameters(config, {find_kernel("levoy")});
    const auto lookup =
        std::find_if(found.begin(), found.end(), [](const auto& p) { return p.key == "gp_cost.cache_lookup_cycles"; });
    ASSERT_NE(lookup, found.end());
    EXPECT_DOUBLE_EQ(lookup->low, 15.0);
    EXPECT_DOUBLE_EQ(lookup->high, 60.0);
    EXPECT_TRUE(lookup->logarithmic);
    // Other kernels' costs cannot move a Levoy frame, and a range fixed by its sources is no guess.
    for (const UncertainParameter& p : found) {
        EXPECT_FALSE(p.key.starts_with("gp_cost.yuan.")) << p.key;
        EXPECT_NE(p.key, "ring.channels");
    }
}

TEST(Uncertainty, TheBandOfAKnownResponseIsTheRectangularDistributions) {
    // y = qee latency * sqrt(header words): straight in the logarithms, so the linearisation is exact.
    const MachineConfig config(run_param_groups());
    std::vector<UncertainParameter> guesses;
    for (const UncertainParameter& p : uncertain_parameters(config, {find_kernel("levoy")}))
        if (p.key == "pp.qee_latency_cycles" || p.key == "ring.header_words") guesses.push_back(p);
    ASSERT_EQ(guesses.size(), 2u);
    const FigureEvaluator figure = [](const MachineConfig& c) {
        return std::vector<double>{static_cast<double>(c.integer("pp.qee_latency_cycles")) *
                                   std::sqrt(static_cast<double>(c.integer("ring.header_words")))};
    };
    const UncertaintyTable table = measure_uncertainty(config, guesses, figure);
    EXPECT_EQ(table.retimings, 5u);  // the base, then each guess at both ends
    ASSERT_EQ(table.parameters.size(), 2u);

    // 4 in [1, 16] and 2 in [1, 4], evenly in ln: variances (ln 16)^2 / 12 and a quarter of (ln 4)^2 / 12.
    const double base = 4.0 * std::sqrt(2.0);
    const double variance = (std::pow(std::log(16.0), 2) + 0.25 * std::pow(std::log(4.0), 2)) / 12.0;
    const double spread = 1.959964 * std::sqrt(variance);
    const Band b = band(table, 0);
    EXPECT_NEAR(b.low, base * std::exp(-spread), 1e-9 * base);
    EXPECT_NEAR(b.high, base * std::exp(spread), 1e-9 * base);
    const Band whole = extremes(table, 0);
    EXPECT_NEAR(whole.low, 1.0, 1e-9);
    EXPECT_NEAR(whole.high, 16.0 * 2.0, 1e-9);
    const std::vector<Contribution> main = main_contributors(table, 0, 5);
    ASSERT_EQ(main.size(), 2u);
    EXPECT_EQ(main[0].key, "pp.qee_latency_cycles");
    EXPECT_NEAR(main[0].share, 16.0 / 17.0, 1e-9);
    // The worst case for a low figure takes both guesses to their low ends.
    const MachineConfig low = worst_case(config, table, 0, true);
    EXPECT_DOUBLE_EQ(figure(low)[0], whole.low);
}

TEST(Uncertainty, APerOperationCostIsReTimedAtItsFarEndOnly) {
    // A time that grows along a straight line with a per-operation cost: the near end drawn is exact.
    const MachineConfig config(run_param_groups());
    std::vector<UncertainParameter> guesses;
    for (const UncertainParameter& p : uncertain_parameters(config, {find_kernel("levoy")}))
        if (p.key == "gp_cost.cache_lookup_cycles") guesses.push_back(p);
    ASSERT_EQ(guesses.size(), 1u);
    EXPECT_TRUE(guesses[0].per_operation);
    const FigureEvaluator figure = [](const MachineConfig& c) {
        return std::vector<double>{100.0 + 10.0 * c.real("gp_cost.cache_lookup_cycles")};
    };
    const UncertaintyTable table = measure_uncertainty(config, guesses, figure);
    EXPECT_EQ(table.retimings, 2u);
    EXPECT_EQ(table.drawn_ends, 1u);
    ASSERT_EQ(table.parameters.size(), 1u);
    EXPECT_NEAR(table.response[0][0].at_low, std::log(150.0 / 200.0), 1e-12);   // at 5 cycles
    EXPECT_NEAR(table.response[0][0].at_high, std::log(300.0 / 200.0), 1e-12);  // at 20, re-timed
}

TEST(Uncertainty, TheBandHoldsTheFramesOfMachinesDrawnFromTheRanges) {
    const test::CalibrationFiles files = test::write_calibration_files("uncertainty");
    const MachineConfig machine = load_run_config(files.machine.string(), {});
    const RecordedScenario recording(load_scenario(files.scenario), machine, 3);
    const FigureEvaluator frame_seconds = [&](const MachineConfig& c) {
        std::vector<double> seconds;
        for (const FrameTiming& t : recording.time_on(c)) seconds.push_back(ticks_to_seconds(t.duration_ps()));
        return seconds;
    };
    const std::vector<UncertainParameter> guesses = uncertain_parameters(machine, {&recording.kernel()});
    const UncertaintyTable table = measure_uncertainty(machine, guesses, frame_seconds);
    ASSERT_GT(table.parameters.size(), 10u);

    // Machines drawn from the ranges, each guess spread as the table assumes it is.
    std::mt19937_64 random(20261205);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    constexpr int kDraws = 48;
    std::vector<std::vector<double>> drawn(table.base.size());
    for (int d = 0; d < kDraws; ++d) {
        MachineConfig c = machine;
        for (const UncertainParameter& p : guesses) {
            const double u = unit(random);
            double x = p.logarithmic ? std::exp(std::log(p.low) + u * (std::log(p.high) - std::log(p.low)))
                                     : p.low + u * (p.high - p.low);
            if (p.integer) c.set(p.key, static_cast<std::int64_t>(std::llround(x)), "draw");
            else c.set(p.key, x, "draw");
        }
        const std::vector<double> seconds = frame_seconds(c);
        for (std::size_t f = 0; f < seconds.size(); ++f) drawn[f].push_back(seconds[f]);
    }
    for (std::size_t f = 0; f < table.base.size(); ++f) {
        const Band b = band(table, f);
        const Band whole = extremes(table, f);
        EXPECT_LT(b.low, table.base[f]);
        EXPECT_GT(b.high, table.base[f]);
        const auto inside =
            std::count_if(drawn[f].begin(), drawn[f].end(), [&](double s) { return s >= b.low && s <= b.high; });
        // 95% nominal: at least 40 of 48 draws, allowing for the linearisation and the draw.
        EXPECT_GE(inside, 40) << "frame " << f << ": band [" << b.low << ", " << b.high << "]";
        // And the band is no wider than it needs to be: the draws reach well into it on both sides.
        std::sort(drawn[f].begin(), drawn[f].end());
        const double drawn_width = std::log(drawn[f].back() / drawn[f].front());
        EXPECT_GT(drawn_width, 0.5 * std::log(b.high / b.low)) << "frame " << f;
        EXPECT_LE(whole.low, b.low);
        EXPECT_GE(whole.high, b.high);
    }
}

}  // namespace
}  // namespace pp5
