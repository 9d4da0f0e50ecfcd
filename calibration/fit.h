#pragma once
// `pp5sim fit`: Ceres least squares over the calibration's scale factors, machine by machine (the
// Pixel-planes 5 and Sun 4/280 scales share nothing, so each machine's are fitted to its own targets).
//
// A target's residual is log(simulated / reported) divided by its source's relative uncertainty
// (targets.h), under a Cauchy loss so that one figure the model cannot reach does not drag the rest.
// Before fitting, each scale's effect on the fitted targets is measured; a scale that moves no target
// by 2% over a 10% change, or one the others mimic (the Jacobian's columns nearly parallel), is
// reported as not identifiable and held at 1. A machine frees fewer scales than half its fitted targets:
// beyond that, the scale that moves them least is held too.
// After the fit: standard errors from Ceres' covariance (scaled up by the residuals' spread when it
// exceeds their stated uncertainty), and the leave-one-out prediction of every fitted target.

#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "calibration/workload.h"

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

struct FittedParameter {
    std::string machine;
    std::string key;  // "calibration.gp_flops_scale"
    double value = 1.0;
    double standard_error = 0.0;  // NaN when not computable
    double lower = 0.0;
    double upper = 0.0;
    bool free = true;             // fitted; false: held at its value, `note` says why
    bool at_bound = false;
    std::string provenance;       // what the bounds come from
    std::string note;
};

struct TargetResult {
    Target target;
    double simulated = 0.0;
    double relative_error = 0.0;                   // (simulated - reported) / reported
    std::optional<double> uncalibrated;            // at the machine file's own scales, beside the fit
    std::optional<double> leave_one_out;           // predicted without this target (fitted targets only)
    std::optional<double> leave_one_out_error;
    std::string leave_one_out_note;
};

struct ErrorSummary {
    int count = 0;
    double mean_absolute_error = 0.0;  // of relative errors
    double max_absolute_error = 0.0;
    int within_10 = 0;
    int within_25 = 0;
    double log_correlation = 0.0;      // Pearson r of log(simulated) against log(reported)
};

struct FitReport {
    std::string targets_name;
    std::vector<IdentifiedWorkload> workload;  // the workload step's results, before the fit (workload.h)
    std::vector<FittedParameter> parameters;
    std::vector<TargetResult> results;
    ErrorSummary fitted;
    ErrorSummary held_out;
    ErrorSummary all;
    // Every row's errors by the metric's unit (s, 1/s, ratio...): figures in different units are
    // judged apart, as their plots are drawn apart.
    std::vector<std::pair<std::string, ErrorSummary>> by_unit() const;
    std::vector<std::string> notes;  // per machine: iterations, cost, termination
    double host_seconds = 0.0;

    CalibrationScales scales(const std::string& machine) const;
    // "fitted", "held out", with "; workload" when the workload step used the row.
    std::string use_of(const Target& target) const;
    nlohmann::json to_json() const;
    std::string to_markdown() const;
};

struct FitOptions {
    bool leave_one_out = true;
    int max_iterations = 50;
    std::function<void(const std::string&)> progress;  // a line per step, may be empty
};

FitReport fit_targets(const CalibrationModel& model, const FitOptions& options);

// Evaluates every target at given scales (no fit): the report of an uncalibrated or fixed model.
FitReport evaluate_targets(const CalibrationModel& model, const std::map<std::string, CalibrationScales>& scales);

// The machine file `machine` with its [calibration] table replaced by the fitted scales (and their
// standard errors as comments), named "<name>-fitted".
std::string fitted_machine_file(const CalibrationModel& model, const FitReport& report, const std::string& machine);

ErrorSummary summarize(const std::vector<TargetResult>& results, bool fitted, bool held_out);

}  // namespace pp5
