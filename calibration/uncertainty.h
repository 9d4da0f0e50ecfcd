#pragma once
// How far a simulated figure could move if the documented guesses moved within their plausible ranges
// (ParamSpec::plausible). Each guess is taken as spread evenly over its range (evenly in its logarithm
// when the range does not reach zero, as a factor of two either way is a statement about ratios), the
// guesses independent of one another, as a metrologist propagates a rectangular uncertainty (GUM, JCGM
// 100:2008, 4.3.7).
//
// The figure's response is measured, not assumed: the recorded work is re-timed with each guess at
// either end of its range (the rest at their values), and the response between its value and each
// end is taken as straight in the figure's logarithm. A per-operation cost, or a minor guess (its far
// end moves no figure by 2%), has its near end drawn on the straight line through the far one instead
// of re-timed: a frame's time is a sum of such costs along its busiest path, so the line errs, if at
// all, towards a wider band. That captures a
// guess that matters on one side only (fewer ray contexts starve the GPs; more barely help). The
// responses add; their mean and variance give the 95% band, clipped to the box every guess at its
// worst end would reach. Calibration scales are not guesses of this kind: the fit measures them, and
// its covariance gives a fitted machine's intervals (calibration/fit.h).

#include "sim/core/config.h"

#include <cstddef>
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace pp5 {

class Kernel;

struct UncertainParameter {
    std::string key;
    double value = 0.0;  // on the machine
    double low = 0.0;    // the plausible range on this machine (the declared range as factors of
    double high = 0.0;   //   the default, when the machine file sets another value)
    bool integer = false;
    bool logarithmic = false;    // spread evenly in ln (the range does not reach zero)
    bool per_operation = false;  // a per-operation cost (PlausibleRange::per_operation)
    std::string why;
};

// Every timing parameter of `config` whose plausible range is more than a point, but the calibration's
// scales, the cost tables of kernels other than `in_use`, and the keys in `fixed` (a sweep's own axes,
// which the user chose rather than guessed).
std::vector<UncertainParameter> uncertain_parameters(const MachineConfig& config,
                                                     const std::vector<const Kernel*>& in_use,
                                                     const std::set<std::string>& fixed = {});

// A figure's response to one guess: how much it moves (in ln when the figure is positive) with the
// guess at the low and at the high end of its range, and where the value sits in that range.
struct GuessResponse {
    double at_low = 0.0;
    double at_high = 0.0;
    double low_share = 0.0;  // (value - low) / (high - low), in the guess's own scale
    double mean() const;     // over the guess spread evenly across its range
    double variance() const;
};

// What several figures (a frame's times, a table's rows) do as each guess moves.
struct UncertaintyTable {
    std::vector<UncertainParameter> parameters;        // the guesses that move some figure
    std::vector<std::string> refused;                  // "key = value: why" for ends the machine cannot take
    std::vector<double> base;                          // each figure with every guess at its value
    std::vector<bool> logarithmic;                     // per figure: responses in ln (a positive figure)
    std::vector<std::vector<GuessResponse>> response;  // [parameter][figure]
    std::size_t retimings = 0;                         // how many re-timings the table took
    std::size_t drawn_ends = 0;                        // near ends of minor guesses drawn, not re-timed
};

// The figures of a machine configuration: throws InputError (or std::runtime_error from a watchdog)
// when the machine cannot take a value.
using FigureEvaluator = std::function<std::vector<double>(const MachineConfig&)>;

// Measures `figures` on `config` with every parameter in `parameters` at each end of its range.
UncertaintyTable measure_uncertainty(const MachineConfig& config, const std::vector<UncertainParameter>& parameters,
                                     const FigureEvaluator& figures);

struct Band {
    double low = 0.0;
    double high = 0.0;
};

// Figure `figure`'s 95% band. `value` is the figure the band is around: the table's own base value, or
// another configuration's (a sweep point the table was not measured at), moved as the table says.
Band band(const UncertaintyTable& table, std::size_t figure, double value);
Band band(const UncertaintyTable& table, std::size_t figure);
// What the figure reaches with every guess at whichever end of its range moves it furthest down (or
// up), added as the table measured them: the whole range, not 95% of it.
Band extremes(const UncertaintyTable& table, std::size_t figure);

struct Contribution {
    std::string key;
    double share = 0.0;  // of the figure's variance
};
// The guesses that matter most to a figure, largest share first, at most `count`.
std::vector<Contribution> main_contributors(const UncertaintyTable& table, std::size_t figure, std::size_t count);

// The configuration with every guess at the end of its range that moves `figure` down (`downward`)
// or up: where a conclusion is checked by re-timing rather than by the table's sums.
MachineConfig worst_case(const MachineConfig& config, const UncertaintyTable& table, std::size_t figure, bool downward);

}  // namespace pp5
