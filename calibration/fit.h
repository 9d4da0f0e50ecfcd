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
// exceeds their stated uncertainty), and the leave-one-out prediction of every fitted target. A row the
// workload step used is left out of that step too: its parameters are identified again without it (or
// fall back to the machine file's value when they came from it), so no prediction has seen its row.
//
// Rows are counted apart by what they are for (RowGroup): only predictions make the predicted totals.
// A machine's degrees of freedom are its fitted rows less its free scales and the workload parameters
// identified from its rows.

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
    bool free = true;  // fitted; false: held at its value, `note` says why
    bool at_bound = false;
    std::string provenance;  // what the bounds come from
    std::string note;
};

struct TargetResult {
    Target target;
    double simulated = 0.0;
    double relative_error = 0.0;         // (simulated - reported) / reported
    std::optional<double> uncalibrated;  // at the machine file's own scales, beside the fit
    // The uncalibrated value's 95% band over the documented guesses' plausible ranges
    // (calibration/uncertainty_report.h); absent until measured.
    std::optional<double> plausible_low, plausible_high;
    // The 95% interval the fitted scales' covariance gives the simulated value (linearised: the row's
    // elasticities to the free scales, measured by re-timing); absent when no scale of its machine is fitted.
    std::optional<double> low, high;
    std::optional<double> leave_one_out;  // predicted without this target (fitted targets only)
    std::optional<double> leave_one_out_error;
    std::string leave_one_out_note;
};

// Where a row's error is counted: fitted rows, rows the workload step matched (whatever their use),
// predictions, and the rows that test something other than the model (TargetUse).
enum class RowGroup { Fitted, Workload, Predicted, Check, ByConstruction, Comparison };
inline constexpr RowGroup kRowGroups[] = {RowGroup::Fitted, RowGroup::Workload,       RowGroup::Predicted,
                                          RowGroup::Check,  RowGroup::ByConstruction, RowGroup::Comparison};
std::string_view to_string(RowGroup group);  // "fitted", "workload", "predicted", "check", ...
std::string_view describe(RowGroup group);   // a heading for the report

// How freely one machine's fit is determined.
struct MachineFreedom {
    std::string machine;
    int rows = 0;  // its fitted rows, the workload step's among them
    int free_scales = 0;
    int workload_parameters = 0;      // identified from its rows' ratios
    double reduced_chi_square = 0.0;  // NaN without degrees of freedom
    // The free scales' keys and the covariance of their logarithms (row-major), widened by the spread
    // as the standard errors are; empty when Ceres could not compute it.
    std::vector<std::string> free_keys;
    std::vector<double> log_covariance;
    int degrees_of_freedom() const { return rows - free_scales - workload_parameters; }
};

struct ErrorSummary {
    int count = 0;
    double mean_absolute_error = 0.0;  // of relative errors
    double max_absolute_error = 0.0;
    int within_10 = 0;
    int within_25 = 0;
    double log_correlation = 0.0;  // Pearson r of log(simulated) against log(reported)
};

struct FitReport {
    std::string targets_name;
    std::vector<IdentifiedWorkload> workload;  // the workload step's results, before the fit (workload.h)
    std::vector<FittedParameter> parameters;
    std::vector<TargetResult> results;
    std::vector<MachineFreedom> freedom;  // machines with free scales

    RowGroup group_of(const Target& target) const;
    ErrorSummary summary(RowGroup group) const;
    // The model's rows (fitted, workload and predicted) by the metric's unit (s, 1/s, ratio...):
    // figures in different units are judged apart, as their plots are drawn apart.
    std::vector<std::pair<std::string, ErrorSummary>> by_unit() const;
    std::vector<std::string> notes;  // per machine: iterations, cost, termination
    double host_seconds = 0.0;

    CalibrationScales scales(const std::string& machine) const;
    bool used_by_workload(const Target& target) const;
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

ErrorSummary summarize(const std::vector<const TargetResult*>& results);

}  // namespace pp5
