#include "calibration/uncertainty.h"

#include "calibration/timing_model.h"
#include "kernels/api/kernel.h"
#include "kernels/registry/registry.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace pp5 {

namespace {

constexpr double kNormal95 = 1.959964;  // the normal distribution's 95% two-sided factor
constexpr double kRoundingOnly = 1e-9;  // a response this small is rounding, not a guess that matters
constexpr double kMinorChange = 0.02;   // a guess whose far end moves no figure by more than this fraction is minor

double number_of(const ParamValue& v) {
    if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
    return std::get<double>(v);
}

ParamValue as_param(const UncertainParameter& p, double x) {
    return p.integer ? ParamValue(static_cast<std::int64_t>(std::llround(x))) : ParamValue(x);
}

// Where `x` sits in the parameter's range, in the scale its spread is even in.
double scale_of(const UncertainParameter& p, double x) { return p.logarithmic ? std::log(x) : x; }

// The cost groups of kernels a run does not use: re-timing with them moved changes nothing.
std::vector<std::string> unused_cost_prefixes(const std::vector<const Kernel*>& in_use) {
    std::vector<std::string> prefixes;
    for (const Kernel* kernel : kernels()) {
        if (std::find(in_use.begin(), in_use.end(), kernel) != in_use.end()) continue;
        for (const ParamGroup* group : kernel->param_groups())
            if (group->prefix().starts_with("gp_cost.")) prefixes.push_back(group->prefix() + ".");
    }
    return prefixes;
}

}  // namespace

std::vector<UncertainParameter> uncertain_parameters(const MachineConfig& config,
                                                     const std::vector<const Kernel*>& in_use,
                                                     const std::set<std::string>& fixed) {
    const std::vector<std::string> unused = unused_cost_prefixes(in_use);
    std::vector<UncertainParameter> found;
    for (const ParamGroup* group : config.groups()) {
        for (const ParamSpec& spec : group->specs()) {
            const std::string key = group->prefix() + "." + spec.name;
            if (!spec.plausible || !is_timing_parameter(key) || key.starts_with("calibration.") || fixed.count(key))
                continue;
            if (std::any_of(unused.begin(), unused.end(), [&](const std::string& p) { return key.starts_with(p); }))
                continue;
            const bool integer = spec.type == ParamType::Integer;
            const double value = integer ? static_cast<double>(config.integer(key)) : config.real(key);
            const double def = number_of(spec.default_value);
            double low = spec.plausible->low, high = spec.plausible->high;
            if (value != def) {
                // Another machine's value: the same uncertainty, as factors of it.
                if (def == 0.0) continue;  // a range about zero says nothing about another value
                low = value * low / def, high = value * high / def;
                if (low > high) std::swap(low, high);
                if (integer) low = std::floor(low), high = std::ceil(high);
                if (spec.min) low = std::max(low, *spec.min);
                if (spec.max) high = std::min(high, *spec.max);
            }
            if (!(high > low)) continue;  // fixed by its sources
            found.push_back({key, value, low, high, integer, low > 0.0 && value > 0.0, spec.plausible->per_operation,
                             spec.plausible->why});
        }
    }
    return found;
}

double GuessResponse::mean() const { return (at_low * low_share + at_high * (1.0 - low_share)) / 2.0; }

double GuessResponse::variance() const {
    const double square = (at_low * at_low * low_share + at_high * at_high * (1.0 - low_share)) / 3.0;
    return std::max(0.0, square - mean() * mean());
}

namespace {

// One end of a guess's range, re-timed (figures) or drawn, or refused by the machine (refusal).
struct RangeEnd {
    std::size_t parameter;
    bool high;
    double value;
    std::optional<std::vector<double>> figures;
    std::string refusal;
};

// Re-times the ends not yet known (a drawn end is), side by side.
void retime(std::vector<RangeEnd>& ends, const MachineConfig& config, const std::vector<UncertainParameter>& parameters,
            const FigureEvaluator& figures, UncertaintyTable& table) {
    std::vector<RangeEnd*> unknown;
    for (RangeEnd& end : ends)
        if (!end.figures) unknown.push_back(&end);
    pp5::parallel_for(std::size_t{0}, unknown.size(), [&](std::size_t e) {
        RangeEnd& end = *unknown[e];
        const UncertainParameter& p = parameters[end.parameter];
        MachineConfig moved = config;
        try {
            moved.set(p.key, as_param(p, end.value), "plausible range");
            end.figures = figures(moved);
        } catch (const InputError& error) {
            end.refusal = error.what();
        } catch (const std::runtime_error& error) {
            end.refusal = error.what();  // a frame the watchdog stopped: not a machine that could be
        }
    });
    table.retimings += unknown.size();
}

// Each guess's far end: the end of its range further from its value, in the scale its spread is even in.
std::vector<RangeEnd> far_ends(const std::vector<UncertainParameter>& parameters) {
    std::vector<RangeEnd> ends;
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        const UncertainParameter& p = parameters[i];
        const bool high_is_far =
            p.high > p.value && scale_of(p, p.high) - scale_of(p, p.value) >= scale_of(p, p.value) - scale_of(p, p.low);
        ends.push_back({i, high_is_far, high_is_far ? p.high : p.low, std::nullopt, {}});
    }
    return ends;
}

// The near ends: to be re-timed for a guess whose far end moved some figure measurably (or was
// refused); drawn on the straight line through its value and its far end for the others.
std::vector<RangeEnd> near_ends(const std::vector<RangeEnd>& far, const std::vector<UncertainParameter>& parameters,
                                UncertaintyTable& table) {
    std::vector<RangeEnd> near;
    for (const RangeEnd& end : far) {
        const UncertainParameter& p = parameters[end.parameter];
        const double other = end.high ? p.low : p.high;
        if (other == p.value) continue;
        bool measurable = !end.figures;  // a refused far end: the near one must speak for the guess
        for (std::size_t f = 0; end.figures && !p.per_operation && f < table.base.size(); ++f)
            if (std::isfinite(table.base[f]))  // a figure the frame does not have says nothing
                measurable = measurable ||
                             !(std::abs((*end.figures)[f] - table.base[f]) <= kMinorChange * std::abs(table.base[f]));
        if (measurable) {
            near.push_back({end.parameter, !end.high, other, std::nullopt, {}});
            continue;
        }
        std::vector<double> drawn;
        const double along = (other - p.value) / (end.value - p.value);
        for (std::size_t f = 0; f < table.base.size(); ++f)
            drawn.push_back(table.base[f] + ((*end.figures)[f] - table.base[f]) * along);
        near.push_back({end.parameter, !end.high, other, std::move(drawn), {}});
        ++table.drawn_ends;
    }
    return near;
}

// A figure is followed in its logarithm when it and every moved value are positive.
std::vector<bool> logarithmic_figures(const std::vector<double>& base, const std::vector<RangeEnd>& ends) {
    std::vector<bool> logarithmic(base.size(), true);
    for (std::size_t f = 0; f < base.size(); ++f) {
        bool positive = base[f] > 0.0;
        for (const RangeEnd& end : ends)
            if (end.figures) positive = positive && (*end.figures)[f] > 0.0;
        logarithmic[f] = positive;
    }
    return logarithmic;
}

// Each guess's responses from its two ends. A refused end stops its range at the guess's value, and a
// guess that moves no figure beyond rounding is left out of the table.
void record_responses(UncertaintyTable& table, const std::vector<UncertainParameter>& parameters,
                      const std::vector<RangeEnd>& ends) {
    const auto moved_by = [&](std::size_t f, double value) {
        return table.logarithmic[f] ? std::log(value / table.base[f]) : value - table.base[f];
    };
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        UncertainParameter p = parameters[i];
        const RangeEnd* low = nullptr;
        const RangeEnd* high = nullptr;
        for (const RangeEnd& end : ends) {
            if (end.parameter != i) continue;
            if (!end.figures) {
                table.refused.push_back(fmt::format("{} = {}: {}", p.key, end.value, end.refusal));
                (end.high ? p.high : p.low) = p.value;  // the range stops where the machine does
                continue;
            }
            (end.high ? high : low) = &end;
        }
        if (!(p.high > p.low)) continue;
        const double low_share =
            (scale_of(p, p.value) - scale_of(p, p.low)) / (scale_of(p, p.high) - scale_of(p, p.low));
        std::vector<GuessResponse> responses;
        bool moves = false;
        for (std::size_t f = 0; f < table.base.size(); ++f) {
            GuessResponse r{low ? moved_by(f, (*low->figures)[f]) : 0.0, high ? moved_by(f, (*high->figures)[f]) : 0.0,
                            low_share};
            moves = moves || std::abs(r.at_low) > kRoundingOnly || std::abs(r.at_high) > kRoundingOnly;
            responses.push_back(r);
        }
        if (!moves) continue;
        table.parameters.push_back(std::move(p));
        table.response.push_back(std::move(responses));
    }
}

}  // namespace

UncertaintyTable measure_uncertainty(const MachineConfig& config, const std::vector<UncertainParameter>& parameters,
                                     const FigureEvaluator& figures) {
    UncertaintyTable table;
    table.base = figures(config);
    ++table.retimings;
    // Every guess at the far end of its range first; then the near end of the guesses that moved some
    // figure measurably. A guess that did not has its near end drawn: it adds little to any band either way.
    std::vector<RangeEnd> ends = far_ends(parameters);
    retime(ends, config, parameters, figures, table);
    std::vector<RangeEnd> near = near_ends(ends, parameters, table);
    retime(near, config, parameters, figures, table);
    ends.insert(ends.end(), std::make_move_iterator(near.begin()), std::make_move_iterator(near.end()));
    table.logarithmic = logarithmic_figures(table.base, ends);
    record_responses(table, parameters, ends);
    return table;
}

namespace {

Band around(const UncertaintyTable& table, std::size_t figure, double value, double down, double up) {
    if (table.logarithmic[figure]) return {value * std::exp(down), value * std::exp(up)};
    return {value + down, value + up};
}

}  // namespace

Band extremes(const UncertaintyTable& table, std::size_t figure) {
    double down = 0.0, up = 0.0;
    for (const auto& responses : table.response) {
        const GuessResponse& r = responses[figure];
        down += std::min({0.0, r.at_low, r.at_high});
        up += std::max({0.0, r.at_low, r.at_high});
    }
    return around(table, figure, table.base[figure], down, up);
}

Band band(const UncertaintyTable& table, std::size_t figure, double value) {
    double mean = 0.0, variance = 0.0, down = 0.0, up = 0.0;
    for (const auto& responses : table.response) {
        const GuessResponse& r = responses[figure];
        mean += r.mean();
        variance += r.variance();
        down += std::min({0.0, r.at_low, r.at_high});
        up += std::max({0.0, r.at_low, r.at_high});
    }
    const double spread = kNormal95 * std::sqrt(variance);
    // A sum of few guesses, one of them dominant, is flatter than a normal: never beyond every guess at its worst.
    return around(table, figure, value, std::max(down, mean - spread), std::min(up, mean + spread));
}

Band band(const UncertaintyTable& table, std::size_t figure) { return band(table, figure, table.base[figure]); }

std::vector<Contribution> main_contributors(const UncertaintyTable& table, std::size_t figure, std::size_t count) {
    double total = 0.0;
    std::vector<Contribution> all;
    for (std::size_t i = 0; i < table.parameters.size(); ++i) {
        const double v = table.response[i][figure].variance();
        total += v;
        all.push_back({table.parameters[i].key, v});
    }
    if (total <= 0.0) return {};
    for (Contribution& c : all) c.share /= total;
    std::stable_sort(all.begin(), all.end(),
                     [](const Contribution& a, const Contribution& b) { return a.share > b.share; });
    all.erase(std::remove_if(all.begin(), all.end(), [](const Contribution& c) { return c.share <= 0.0; }), all.end());
    if (all.size() > count) all.resize(count);
    return all;
}

MachineConfig worst_case(const MachineConfig& config, const UncertaintyTable& table, std::size_t figure,
                         bool downward) {
    MachineConfig moved = config;
    for (std::size_t i = 0; i < table.parameters.size(); ++i) {
        const UncertainParameter& p = table.parameters[i];
        const GuessResponse& r = table.response[i][figure];
        const double sign = downward ? -1.0 : 1.0;
        const double best = std::max({0.0, sign * r.at_low, sign * r.at_high});
        if (best <= 0.0) continue;
        moved.set(p.key, as_param(p, sign * r.at_low == best ? p.low : p.high), "plausible range");
    }
    return moved;
}

}  // namespace pp5
