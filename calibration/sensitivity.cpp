#include "calibration/sensitivity.h"

#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pp5 {

namespace {

constexpr double kStep = 1.1;
constexpr double kMovesNothing = 1e-3;   // an elasticity below this moves no row measurably
constexpr double kWeakestLever = 0.02;   // a what-if needs at least this elasticity on its row
constexpr double kLargestChange = 20.0;  // nor a change of more than this factor, where a line says little
constexpr double kReconciled = 0.01;     // within 1% of the reported value (in log units)
constexpr int kMostRefinements = 4;

struct Candidate {
    std::string key;
    double value = 0.0;
    bool integer = false;
    std::optional<double> lower, upper;
};

std::vector<Candidate> timing_parameters(const MachineConfig& config) {
    std::vector<Candidate> found;
    for (const ParamGroup* group : config.groups()) {
        for (const ParamSpec& spec : group->specs()) {
            const std::string key = group->prefix() + "." + spec.name;
            if (!is_timing_parameter(key) || key.starts_with("calibration.")) continue;
            if (spec.type != ParamType::Integer && spec.type != ParamType::Real) continue;
            const bool integer = spec.type == ParamType::Integer;
            const double value = integer ? static_cast<double>(config.integer(key)) : config.real(key);
            if (!(value > 0.0)) continue;  // nothing to scale
            found.push_back({key, value, integer, spec.min, spec.max});
        }
    }
    return found;
}

// `value` as the parameter can hold it: inside its range, whole for a count.
double admissible(const Candidate& c, double value) {
    if (c.integer) value = std::max(1.0, std::round(value));
    if (c.lower) value = std::max(value, *c.lower);
    if (c.upper) value = std::min(value, *c.upper);
    return value;
}

bool outside_range(const Candidate& c, double value) {
    return (c.lower && value < *c.lower) || (c.upper && value > *c.upper);
}

ParamValue param_value(const Candidate& c, double value) {
    return c.integer ? ParamValue(static_cast<std::int64_t>(std::llround(value))) : ParamValue(value);
}

// The rows re-timed with one parameter at `value`; nullopt when the machine cannot take it.
std::optional<std::vector<double>> retimed(const CalibrationModel& model, const MachineConfig& base, const Candidate& c,
                                           double value, const std::vector<const Target*>& rows) {
    MachineConfig config = base;
    try {
        config.set(c.key, param_value(c, value), "what-if");
        return model.simulate_on(config, rows);
    } catch (const InputError&) {
        return std::nullopt;  // a value the machine refuses (a cache that no longer fits, say)
    } catch (const std::runtime_error&) {
        return std::nullopt;  // a frame the watchdog stopped: far outside what the machine could be
    }
}

}  // namespace

MachineSensitivity measure_sensitivity(const CalibrationModel& model, const std::string& machine,
                                       const CalibrationScales& scales, std::vector<const Target*> rows) {
    MachineSensitivity s;
    s.machine = machine;
    s.scales = scales;
    s.rows = std::move(rows);
    const MachineConfig base = model.machine_config(machine, scales);
    s.simulated = model.simulate_on(base, s.rows);
    const std::vector<Candidate> candidates = timing_parameters(base);
    std::vector<std::optional<ParameterElasticity>> measured(candidates.size());
    pp5::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t i) {
        const Candidate& c = candidates[i];
        double moved =
            admissible(c, c.integer ? std::max(c.value + 1.0, std::round(c.value * kStep)) : c.value * kStep);
        if (moved == c.value) moved = admissible(c, c.integer ? c.value - 1.0 : c.value / kStep);  // at its upper bound
        if (moved == c.value || !(moved > 0.0)) return;
        const std::optional<std::vector<double>> values = retimed(model, base, c, moved, s.rows);
        if (!values) return;
        ParameterElasticity e{c.key, c.value, c.integer, c.lower, c.upper, {}};
        bool moves = false;
        for (std::size_t r = 0; r < s.rows.size(); ++r) {
            e.elasticity.push_back(std::log((*values)[r] / s.simulated[r]) / std::log(moved / c.value));
            moves = moves || std::abs(e.elasticity.back()) > kMovesNothing;
        }
        if (moves) measured[i] = std::move(e);
    });
    for (auto& e : measured)
        if (e) s.parameters.push_back(std::move(*e));
    return s;
}

std::optional<WhatIf> reconcile(const CalibrationModel& model, const MachineSensitivity& s, std::size_t row) {
    const double miss = std::log(s.rows[row]->reported / s.simulated[row]);  // the log change the row needs
    // By the elasticities: the change each parameter needs, and how much it would move the other rows.
    const ParameterElasticity* best = nullptr;
    double best_collateral = std::numeric_limits<double>::infinity();
    for (const ParameterElasticity& p : s.parameters) {
        if (std::abs(p.elasticity[row]) < kWeakestLever) continue;
        const double change = miss / p.elasticity[row];
        if (std::abs(change) > std::log(kLargestChange)) continue;
        double collateral = 0.0;
        for (std::size_t r = 0; r < s.rows.size(); ++r)
            if (r != row) collateral += std::pow(p.elasticity[r] * change, 2);
        // Ties (rows no other parameter touches) go to the smaller change.
        collateral += 1e-6 * change * change;
        if (collateral < best_collateral) best = &p, best_collateral = collateral;
    }
    if (best == nullptr) return std::nullopt;

    // Refined by re-timing: secant steps on the logarithm of the parameter.
    const Candidate c{best->key, best->value, best->integer, best->lower, best->upper};
    const MachineConfig base = model.machine_config(s.machine, s.scales);
    WhatIf what{best->key, best->value, best->value, true, s.simulated[row], s.simulated};
    double x0 = std::log(best->value), g0 = -miss;
    double x1 = x0 + miss / best->elasticity[row];
    for (int step = 0; step < kMostRefinements; ++step) {
        const double wanted = std::exp(x1);
        const double value = admissible(c, wanted);
        const std::optional<std::vector<double>> values = retimed(model, base, c, value, s.rows);
        if (!values) break;
        what.to = value;
        what.within_range = !outside_range(c, wanted);
        what.reached = (*values)[row];
        what.others = *values;
        const double g1 = std::log(what.reached / s.rows[row]->reported);
        if (std::abs(g1) < kReconciled || !what.within_range || g1 == g0) break;
        // Never further than the largest change a what-if considers.
        const double reach = std::log(kLargestChange);
        const double next =
            std::clamp(x1 - g1 * (x1 - x0) / (g1 - g0), std::log(best->value) - reach, std::log(best->value) + reach);
        if (next == x1) break;
        x0 = x1, g0 = g1, x1 = next;
        if (c.integer && std::llround(std::exp(x1)) == std::llround(value)) break;
    }
    return what;
}

}  // namespace pp5
