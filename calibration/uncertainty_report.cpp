#include "calibration/uncertainty_report.h"

#include "calibration/uncertainty.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace pp5 {

namespace {

// The kernels that compute `rows`: only their cost tables can move them.
std::vector<const Kernel*> kernels_of(const CalibrationModel& model, const std::vector<const Target*>& rows) {
    std::vector<const Kernel*> in_use;
    for (const Target* t : rows) {
        const Kernel* k = &model.recording(t->scenario).kernel();
        if (std::find(in_use.begin(), in_use.end(), k) == in_use.end()) in_use.push_back(k);
    }
    return in_use;
}

// The busiest share of the ring's capacity over the GPs' busiest share, frame by frame.
std::vector<double> ring_over_gps(const std::vector<FrameTiming>& frames, const MachineConfig& config) {
    std::vector<double> ratios;
    for (const FrameTiming& frame : frames) {
        double ring = 0.0, gps = 0.0;
        for (const PhaseTiming& p : frame.phases) {
            ring += static_cast<double>(p.gp.ring_busy);
            gps += static_cast<double>(p.gp.gp_busy);
        }
        ring /= static_cast<double>(config.integer("ring.channels"));
        gps /= static_cast<double>(config.integer("gp.count"));
        ratios.push_back(gps > 0.0 ? ring / gps : 0.0);
    }
    return ratios;
}

double total_seconds(const std::vector<FrameTiming>& frames) {
    double s = 0.0;
    for (const FrameTiming& f : frames) s += ticks_to_seconds(f.duration_ps());
    return s;
}

MachineConfig with_gps(const MachineConfig& config, std::int64_t count) {
    MachineConfig c = config;
    c.set("gp.count", count, "conclusion");
    return c;
}

// The guesses a worst case moved, those that work against the claim most first.
std::vector<std::string> moved_guesses(const UncertaintyTable& table, std::size_t figure, bool downward,
                                       const MachineConfig& worst) {
    std::vector<std::pair<double, std::string>> moved;
    for (std::size_t i = 0; i < table.parameters.size(); ++i) {
        const GuessResponse& r = table.response[i][figure];
        const double against = downward ? -std::min({0.0, r.at_low, r.at_high}) : std::max({0.0, r.at_low, r.at_high});
        if (against <= 0.0) continue;
        const std::string& key = table.parameters[i].key;
        const ParamSpec* spec = worst.find_spec(key);
        const std::string value = spec && spec->type == ParamType::Integer ? fmt::format("{}", worst.integer(key))
                                                                           : fmt::format("{:g}", worst.real(key));
        moved.emplace_back(against, key + " = " + value);
    }
    std::stable_sort(moved.begin(), moved.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<std::string> out;
    for (std::size_t i = 0; i < moved.size() && i < 3; ++i) out.push_back(moved[i].second);
    return out;
}

// The claim's figure at its worst: the table's worst case for each figure, re-timed, the worst of them kept.
struct Worst {
    double value = 0.0;
    std::vector<std::string> against;
};

Worst worst_of(const MachineConfig& config, const UncertaintyTable& table, const FigureEvaluator& figures,
               bool downward) {
    Worst worst{downward ? INFINITY : -INFINITY, {}};
    for (std::size_t f = 0; f < table.base.size(); ++f) {
        const MachineConfig moved = worst_case(config, table, f, downward);
        const double value = figures(moved)[f];
        if (downward ? value < worst.value : value > worst.value)
            worst = {value, moved_guesses(table, f, downward, moved)};
    }
    return worst;
}

}  // namespace

void add_plausible_bands(const CalibrationModel& model, FitReport& report) {
    std::map<std::string, std::vector<TargetResult*>> by_machine;
    for (TargetResult& r : report.results)
        if (!r.target.is_formula()) by_machine[r.target.machine].push_back(&r);
    for (const auto& [machine, results] : by_machine) {
        std::vector<const Target*> rows;
        for (const TargetResult* r : results) rows.push_back(&r->target);
        const MachineConfig& config = model.base_config(machine);
        const UncertaintyTable table =
            measure_uncertainty(config, uncertain_parameters(config, kernels_of(model, rows)),
                                [&](const MachineConfig& c) { return model.simulate_on(c, rows); });
        for (std::size_t i = 0; i < results.size(); ++i) {
            const Band b = band(table, i);
            results[i]->plausible_low = b.low;
            results[i]->plausible_high = b.high;
        }
    }
}

std::vector<Conclusion> check_conclusions(const CalibrationModel& model, const FitReport& report) {
    std::vector<Conclusion> conclusions;
    std::vector<std::string> machines;
    for (const TargetResult& r : report.results) {
        const Target& t = r.target;
        if (t.is_formula() || std::find(machines.begin(), machines.end(), t.machine) != machines.end()) continue;
        if (model.base_config(t.machine).machine_kind() != MachineKind::Multicomputer) continue;
        machines.push_back(t.machine);
        const RecordedScenario& recording = model.recording(t.scenario);
        const MachineConfig config = model.machine_config(t.machine, report.scales(t.machine));
        const std::vector<UncertainParameter> guesses = uncertain_parameters(config, {&recording.kernel()});

        // The ring never the bottleneck: its share of capacity below the GPs' in every frame.
        const FigureEvaluator ring = [&](const MachineConfig& c) { return ring_over_gps(recording.time_on(c), c); };
        const UncertaintyTable ring_table = measure_uncertainty(config, guesses, ring);
        const Worst ring_worst = worst_of(config, ring_table, ring, false);
        const double ring_now = *std::max_element(ring_table.base.begin(), ring_table.base.end());
        conclusions.push_back({"the ring is never the bottleneck", t.scenario, t.machine,
                               "the ring's busy share of its channels over the GPs' busy share, in the frame where it "
                               "is highest (below 1)",
                               ring_now, ring_worst.value, ring_worst.value < 1.0, ring_worst.against});

        // Doubling the GPs speeds the frames up, by at least the worst case's factor.
        const FigureEvaluator doubling = [&](const MachineConfig& c) {
            return std::vector<double>{total_seconds(recording.time_on(with_gps(c, 32))) /
                                       total_seconds(recording.time_on(with_gps(c, 64)))};
        };
        const UncertaintyTable gp_table = measure_uncertainty(config, guesses, doubling);
        const Worst gp_worst = worst_of(config, gp_table, doubling, true);
        conclusions.push_back({"64 GPs beat 32", t.scenario, t.machine,
                               "the frames' time on 32 GPs over their time on 64 (above 1)", gp_table.base[0],
                               gp_worst.value, gp_worst.value > 1.0, gp_worst.against});
    }
    return conclusions;
}

std::string conclusions_markdown(const std::vector<Conclusion>& conclusions) {
    if (conclusions.empty()) return {};
    std::string md =
        "\n## What holds across the plausible range\n\nEach claim is re-timed with every documented guess at the end "
        "of its "
        "plausible range that works against it, each end chosen by that guess's own response (`pp5sim params` gives "
        "the ranges "
        "and their reasons). Guesses that work against a claim only together could take it further; the worst case is "
        "the "
        "corner the guesses one at a time point to.\n\n"
        "| claim | scenario | machine | figure | as configured | at its worst | holds | guesses against it most |\n"
        "|---|---|---|---|---|---|---|---|\n";
    for (const Conclusion& c : conclusions) {
        std::string against;
        for (const std::string& g : c.against) against += (against.empty() ? "`" : ", `") + g + "`";
        md += fmt::format("| {} | {} | {} | {} | {:.3g} | {:.3g} | {} | {} |\n", c.claim, c.scenario, c.machine,
                          c.figure, c.on_machine, c.at_worst, c.holds ? "yes" : "**no**", against);
    }
    return md;
}

nlohmann::json conclusions_json(const std::vector<Conclusion>& conclusions) {
    nlohmann::json out = nlohmann::json::array();
    for (const Conclusion& c : conclusions)
        out.push_back({{"claim", c.claim},
                       {"scenario", c.scenario},
                       {"machine", c.machine},
                       {"figure", c.figure},
                       {"as_configured", c.on_machine},
                       {"at_worst", c.at_worst},
                       {"holds", c.holds},
                       {"guesses_against", c.against}});
    return out;
}

}  // namespace pp5
