#include "calibration/fit.h"

#include "calibration/fit_detail.h"
#include "calibration/identifiability.h"
#include "calibration/machine_fit.h"

#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>

namespace pp5 {

namespace {

using fit_detail::key_of;
using fit_detail::kScaleCount;
using fit_detail::kScales;
using fit_detail::MachineFit;
using fit_detail::number;
using fit_detail::percent;
using fit_detail::ScaleSpec;

CalibrationScales scales_from(const std::map<std::string, double>& values, const std::string& machine) {
    CalibrationScales s;
    for (const ScaleSpec& spec : kScales) {
        const auto it = values.find(machine + "/" + key_of(spec));
        if (it != values.end()) s.*spec.member = it->second;
    }
    return s;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
    const double n = static_cast<double>(a.size());
    if (a.size() < 2) return std::numeric_limits<double>::quiet_NaN();
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : std::numeric_limits<double>::quiet_NaN();
}

// A machine's three scales at `start`, before any fit.
std::vector<ScaleBounds> bounds_of(const MachineConfig& config) {
    std::vector<ScaleBounds> bounds;
    for (const ScaleSpec& spec : kScales) bounds.push_back(scale_bounds(config, spec.name));
    return bounds;
}

// `provenance` overrides the bounds' own source (for scales that are given, not fitted).
std::vector<FittedParameter> initial_parameters(const std::string& machine, const MachineConfig& config,
                                                const CalibrationScales& start, bool free,
                                                const std::string& provenance = {}) {
    const std::vector<ScaleBounds> bounds = bounds_of(config);
    std::vector<FittedParameter> params;
    for (std::size_t i = 0; i < std::size(kScales); ++i) {
        FittedParameter p;
        p.machine = machine;
        p.key = key_of(kScales[i]);
        p.value = start.*kScales[i].member;
        p.standard_error = std::numeric_limits<double>::quiet_NaN();
        p.lower = bounds[i].lower;
        p.upper = bounds[i].upper;
        p.free = free;
        p.provenance = provenance.empty() ? bounds[i].why : provenance;
        params.push_back(p);
    }
    return params;
}

// Fills in every target's simulated value and error at the report's scales.
void evaluate_all(const CalibrationModel& model, FitReport& report) {
    std::map<std::string, std::vector<const Target*>> by_machine;
    std::map<std::string, double> simulated;
    for (const Target& t : model.targets().targets) {
        if (t.is_formula()) simulated[t.id] = model.formula_value(t);
        else by_machine[t.machine].push_back(&t);
    }
    for (const auto& [machine, targets] : by_machine) {
        const std::vector<double> values = model.simulate(machine, report.scales(machine), targets);
        for (std::size_t i = 0; i < targets.size(); ++i) simulated[targets[i]->id] = values[i];
    }
    std::map<std::string, TargetResult> previous;
    for (TargetResult& r : report.results) previous.emplace(r.target.id, r);
    report.results.clear();
    for (const Target& t : model.targets().targets) {
        TargetResult r;
        if (const auto it = previous.find(t.id); it != previous.end()) r = it->second;
        r.target = t;
        r.simulated = simulated[t.id];
        r.relative_error = (r.simulated - t.reported) / t.reported;
        report.results.push_back(r);
    }
}

bool ratio_uses(const WorkloadSpec& spec, const std::string& id) {
    return spec.numerator == id || spec.denominator == id;
}

// The workload parameters the model's recording was made with that came from `machine`'s rows.
int workload_parameters_from(const CalibrationModel& model, const std::string& machine) {
    int count = 0;
    for (const WorkloadSpec& spec : model.targets().workload) {
        const bool identified = std::any_of(model.workload().begin(), model.workload().end(),
                                            [&](const WorkloadSetting& w) { return w.key == spec.key; });
        const Target* row = model.targets().find(spec.numerator);
        count += identified && row != nullptr && row->machine == machine;
    }
    return count;
}

// A fitted row predicted by a fit that never saw it. When the workload step used the row, the step runs
// again without it: parameters identified from its ratio keep the machine file's value, the others are
// identified afresh, and the machine's rows are recorded anew with what that gives.
TargetResult predict_left_out(const CalibrationModel& model, const MachineFit& full, std::size_t k,
                              const FitOptions& options, const std::function<void(const std::string&)>& say) {
    const std::vector<const Target*>& targets = full.targets();
    const Target& left = *targets[k];
    TargetResult result;
    result.target = left;
    std::vector<const Target*> rest;
    for (std::size_t i = 0; i < targets.size(); ++i)
        if (i != k) rest.push_back(targets[i]);
    if (rest.size() < full.free().size()) {
        result.leave_one_out_note =
            fmt::format("not possible: {} targets left for {} scales", rest.size(), full.free().size());
        return result;
    }
    say(fmt::format("{}: leave-one-out: refitting without {}", full.machine(), left.id));

    const bool workload_row =
        !model.workload().empty() && std::any_of(model.targets().workload.begin(), model.targets().workload.end(),
                                                 [&](const WorkloadSpec& spec) { return ratio_uses(spec, left.id); });
    std::unique_ptr<CalibrationModel> rerecorded;
    const CalibrationModel* basis = &model;
    if (workload_row) {
        TargetSet without = model.targets();
        std::erase_if(without.targets, [&](const Target& t) { return t.id == left.id; });
        std::vector<std::string> fallen;
        for (const WorkloadSpec& spec : without.workload)
            if (ratio_uses(spec, left.id)) fallen.push_back(spec.key);
        std::erase_if(without.workload, [&](const WorkloadSpec& spec) { return ratio_uses(spec, left.id); });
        WorkloadOptions identify;
        identify.progress = say;
        const std::vector<IdentifiedWorkload> again = identify_workload(without, identify);
        // The machine's rows only (the left-out one included, to predict it), recorded as the full
        // model's are, with the workload the rest gives.
        TargetSet rows;
        rows.file = model.targets().file;
        rows.name = model.targets().name;
        for (const Target* t : targets) rows.targets.push_back(*t);
        rerecorded =
            std::make_unique<CalibrationModel>(rows, recording_machine(model.targets()), workload_settings(again));
        basis = rerecorded.get();
        std::string note = "workload step rerun without it:";
        for (const IdentifiedWorkload& w : again) note += fmt::format(" {} = {:.4g};", w.spec.key, w.value);
        for (const std::string& key : fallen)
            note += fmt::format(" {} at the machine file's value (its ratio needs this row);", key);
        note.pop_back();
        result.leave_one_out_note = note;
        // The rows as the re-recorded model holds them (the same rows, its own copies).
        rest.clear();
        for (const Target& t : basis->targets().targets)
            if (t.id != left.id) rest.push_back(&t);
    }
    const MachineFit partial = full.on(*basis, rest);
    std::vector<double> y = partial.log_start();
    const ceres::Solver::Summary refit = partial.solve(y, options.max_iterations);
    say(fmt::format("{}: leave-one-out without {}: {} iterations, {} simulations; {}", full.machine(), left.id,
                    refit.iterations.size(), partial.simulations(),
                    refit.termination_type == ceres::CONVERGENCE ? "converged" : "not converged: " + refit.message));
    const Target* predicted_row = basis->targets().find(left.id);
    const double predicted = basis->simulate(full.machine(), partial.scales(y.data()), {predicted_row}).front();
    result.leave_one_out = predicted;
    result.leave_one_out_error = (predicted - left.reported) / left.reported;
    if (rest.size() == full.free().size())
        result.leave_one_out_note +=
            (result.leave_one_out_note.empty() ? "" : "; ") + std::string("the rest determine the scales exactly");
    return result;
}

// Each simulated row's 95% interval from the fitted scales' covariance: var(ln y) = J C J^T, with J the
// row's elasticities to the free scales (central differences of 5% in the logarithm, as the fit's own
// Jacobian), the re-timings of each machine run side by side.
void add_fit_intervals(const CalibrationModel& model, FitReport& report) {
    constexpr double kLogStep = 0.05;
    constexpr double kTwoSided95 = 1.959964;
    for (const MachineFreedom& f : report.freedom) {
        if (f.log_covariance.empty()) continue;
        std::vector<TargetResult*> rows;
        std::vector<const Target*> targets;
        for (TargetResult& r : report.results)
            if (!r.target.is_formula() && r.target.machine == f.machine)
                rows.push_back(&r), targets.push_back(&r.target);
        const CalibrationScales at = report.scales(f.machine);
        const std::size_t n = f.free_keys.size();
        std::vector<std::vector<double>> runs(2 * n);
        pp5::parallel_for(std::size_t{0}, runs.size(), [&](std::size_t run) {
            CalibrationScales moved = at;
            const auto spec = std::find_if(std::begin(kScales), std::end(kScales),
                                           [&](const ScaleSpec& s) { return key_of(s) == f.free_keys[run / 2]; });
            moved.*spec->member *= std::exp(run % 2 == 0 ? kLogStep : -kLogStep);
            runs[run] = model.simulate(f.machine, moved, targets);
        });
        for (std::size_t r = 0; r < rows.size(); ++r) {
            std::vector<double> j(n);
            for (std::size_t i = 0; i < n; ++i) j[i] = std::log(runs[2 * i][r] / runs[2 * i + 1][r]) / (2.0 * kLogStep);
            double variance = 0.0;
            for (std::size_t a = 0; a < n; ++a)
                for (std::size_t b = 0; b < n; ++b) variance += j[a] * f.log_covariance[a * n + b] * j[b];
            const double half = kTwoSided95 * std::sqrt(std::max(0.0, variance));
            rows[r]->low = rows[r]->simulated * std::exp(-half);
            rows[r]->high = rows[r]->simulated * std::exp(half);
        }
    }
}

}  // namespace

ErrorSummary summarize(const std::vector<const TargetResult*>& results) {
    ErrorSummary s;
    std::vector<double> log_simulated, log_reported;
    for (const TargetResult* r : results) {
        ++s.count;
        const double e = std::abs(r->relative_error);
        s.mean_absolute_error += e;
        s.max_absolute_error = std::max(s.max_absolute_error, e);
        s.within_10 += e <= 0.10;
        s.within_25 += e <= 0.25;
        log_simulated.push_back(std::log(r->simulated));
        log_reported.push_back(std::log(r->target.reported));
    }
    if (s.count > 0) s.mean_absolute_error /= s.count;
    s.log_correlation = pearson(log_simulated, log_reported);
    return s;
}

std::string_view to_string(RowGroup group) {
    switch (group) {
        case RowGroup::Fitted: return "fitted";
        case RowGroup::Workload: return "workload";
        case RowGroup::Predicted: return "predicted";
        case RowGroup::Check: return "check";
        case RowGroup::ByConstruction: return "by_construction";
        case RowGroup::Comparison: return "comparison";
    }
    return "?";
}

std::string_view describe(RowGroup group) {
    switch (group) {
        case RowGroup::Fitted: return "fitted";
        case RowGroup::Workload: return "workload step (matched in ratio, then fitted)";
        case RowGroup::Predicted: return "predicted (held out)";
        case RowGroup::Check: return "arithmetic checks";
        case RowGroup::ByConstruction: return "matched by construction";
        case RowGroup::Comparison: return "comparisons (another machine)";
    }
    return "?";
}

bool FitReport::used_by_workload(const Target& target) const {
    return std::any_of(workload.begin(), workload.end(),
                       [&](const IdentifiedWorkload& w) { return ratio_uses(w.spec, target.id); });
}

RowGroup FitReport::group_of(const Target& target) const {
    if (used_by_workload(target)) return RowGroup::Workload;
    switch (target.use) {
        case TargetUse::Fit: return RowGroup::Fitted;
        case TargetUse::Predict: return RowGroup::Predicted;
        case TargetUse::Check: return RowGroup::Check;
        case TargetUse::ByConstruction: return RowGroup::ByConstruction;
        case TargetUse::Comparison: return RowGroup::Comparison;
    }
    return RowGroup::Predicted;
}

ErrorSummary FitReport::summary(RowGroup group) const {
    std::vector<const TargetResult*> rows;
    for (const TargetResult& r : results)
        if (group_of(r.target) == group) rows.push_back(&r);
    return summarize(rows);
}

std::vector<std::pair<std::string, ErrorSummary>> FitReport::by_unit() const {
    std::vector<std::pair<std::string, std::vector<const TargetResult*>>> units;
    for (const TargetResult& r : results) {
        const RowGroup group = group_of(r.target);
        if (group != RowGroup::Fitted && group != RowGroup::Workload && group != RowGroup::Predicted) continue;
        auto it = std::find_if(units.begin(), units.end(), [&](const auto& u) { return u.first == r.target.unit; });
        if (it == units.end()) it = units.insert(units.end(), {r.target.unit, {}});
        it->second.push_back(&r);
    }
    std::vector<std::pair<std::string, ErrorSummary>> summaries;
    for (const auto& [unit, rows] : units) summaries.emplace_back(unit, summarize(rows));
    return summaries;
}

CalibrationScales FitReport::scales(const std::string& machine) const {
    std::map<std::string, double> values;
    for (const FittedParameter& p : parameters) values[p.machine + "/" + p.key] = p.value;
    return scales_from(values, machine);
}

FitReport evaluate_targets(const CalibrationModel& model, const std::map<std::string, CalibrationScales>& scales) {
    FitReport report;
    report.targets_name = model.targets().name;
    std::set<std::string> machines;
    for (const Target& t : model.targets().targets)
        if (!t.is_formula()) machines.insert(t.machine);
    for (const std::string& machine : machines) {
        const auto it = scales.find(machine);
        const CalibrationScales s =
            it != scales.end() ? it->second : CalibrationScales::from(model.base_config(machine));
        const std::vector<FittedParameter> given =
            initial_parameters(machine, model.base_config(machine), s, false, "given, not fitted");
        report.parameters.insert(report.parameters.end(), given.begin(), given.end());
    }
    evaluate_all(model, report);
    return report;
}

namespace {

// A free scale's fitted value from its logarithm, its standard error (none: not computable) and what
// to say about it.
void set_fitted_value(FittedParameter& p, double log_value, std::optional<double> log_variance) {
    // The covariance is of the logarithm; to first order the scale's error is the value times it.
    p.value = std::exp(log_value);
    p.standard_error = log_variance ? p.value * std::sqrt(*log_variance) : std::numeric_limits<double>::quiet_NaN();
    p.at_bound = std::abs(p.value - p.lower) < 1e-6 * p.lower || std::abs(p.value - p.upper) < 1e-6 * p.upper;
    // A scale held by its physical range is a finding about the model, not a fitted value: the
    // targets want a machine the hardware could not be.
    if (p.at_bound)
        p.note = fmt::format(
            "at its {} bound, a finding: the targets ask for a machine {} than this range allows ({}); its "
            "standard error means little",
            p.value <= p.lower * (1 + 1e-6) ? "lower" : "upper", p.value <= p.lower * (1 + 1e-6) ? "faster" : "slower",
            p.provenance);
    else if (std::isfinite(p.standard_error) && p.standard_error > 0.5 * p.value)
        p.note = fmt::format("poorly determined: the standard error is {:.0f}% of the value",
                             100.0 * p.standard_error / p.value);
    if (!log_variance)
        p.note += (p.note.empty() ? "" : "; ") + std::string("covariance not computable (rank-deficient Jacobian)");
}

std::string freedom_note(const std::string& machine, const MachineFreedom& freedom) {
    if (freedom.degrees_of_freedom() > 0)
        return fmt::format(
            "{}: residual spread (reduced chi-square) {:.3g} on {} degrees of freedom ({} rows, {} free scales, {} "
            "workload parameters)",
            machine, freedom.reduced_chi_square, freedom.degrees_of_freedom(), freedom.rows, freedom.free_scales,
            freedom.workload_parameters);
    return fmt::format(
        "{}: no degrees of freedom ({} rows, {} free scales, {} workload parameters): the rows determine the "
        "parameters exactly, so they test nothing, and the standard errors come from the rows' stated "
        "uncertainties alone",
        machine, freedom.rows, freedom.free_scales, freedom.workload_parameters);
}

// Fits the free scales of one machine to its targets: the solution, each scale's standard error from
// Ceres' covariance at it (widened when the residuals spread more than their sources' stated
// uncertainty), and the notes on how the solve went. Returns the fit for the leave-one-out refits.
std::unique_ptr<MachineFit> fit_machine(const CalibrationModel& model, const std::string& machine,
                                        const std::vector<const Target*>& targets, const CalibrationScales& start,
                                        const std::vector<int>& free, const std::vector<ScaleBounds>& bounds,
                                        const FitOptions& options, std::vector<FittedParameter>& params,
                                        FitReport& report, const std::function<void(const std::string&)>& say) {
    auto owned = std::make_unique<MachineFit>(model, machine, targets, start, free, bounds);
    const MachineFit& fit = *owned;
    std::vector<double> x = fit.log_start();
    say(fmt::format("{}: fitting {} scales to {} targets", machine, free.size(), targets.size()));
    const ceres::Solver::Summary summary = fit.solve(x, options.max_iterations);
    report.notes.push_back(
        fmt::format("{}: {} iterations, {} residual evaluations, final cost {:.4g} (from {:.4g}); {}", machine,
                    summary.iterations.size(), summary.num_residual_evaluations, summary.final_cost,
                    summary.initial_cost, summary.message));

    // Standard errors: the covariance widened when the residuals spread more than their sources'
    // stated uncertainty (reduced chi-square above 1). The rows the workload step matched have spent
    // degrees of freedom on its parameters as well as on the scales.
    const std::vector<double> r = fit.residuals(fit.scales(x.data()));
    double chi2 = 0;
    for (double v : r) chi2 += v * v;
    MachineFreedom freedom{machine,
                           static_cast<int>(targets.size()),
                           static_cast<int>(free.size()),
                           workload_parameters_from(model, machine),
                           std::numeric_limits<double>::quiet_NaN(),
                           {},
                           {}};
    if (freedom.degrees_of_freedom() > 0) freedom.reduced_chi_square = chi2 / freedom.degrees_of_freedom();
    const double widening = std::max(1.0, std::isfinite(freedom.reduced_chi_square) ? freedom.reduced_chi_square : 1.0);
    const std::optional<std::vector<double>> cov = fit.log_covariance(x);
    if (cov) {
        for (const int j : free) freedom.free_keys.push_back(key_of(kScales[j]));
        for (const double c : *cov) freedom.log_covariance.push_back(c * widening);
    }
    report.freedom.push_back(freedom);
    for (std::size_t i = 0; i < free.size(); ++i)
        set_fitted_value(params[static_cast<std::size_t>(free[i])], x[i],
                         cov ? std::optional<double>((*cov)[i * x.size() + i] * widening) : std::nullopt);
    report.notes.push_back(freedom_note(machine, freedom));
    return owned;
}

// Leave one out: refit without each fitted target, from the same start as the full fit (not from its
// answer, which has seen the target), and predict it. The refits are independent: they run side by
// side, each deterministic, so the results do not depend on the thread count.
void leave_each_out(const CalibrationModel& model, const MachineFit& fit, const std::vector<const Target*>& targets,
                    const FitOptions& options, const std::function<void(const std::string&)>& say,
                    std::map<std::string, TargetResult>& loo) {
    std::vector<TargetResult> left_out(targets.size());
    std::mutex progress;
    const auto say_locked = [&](const std::string& line) {
        const std::lock_guard<std::mutex> lock(progress);
        say(line);
    };
    pp5::parallel_for(std::size_t{0}, targets.size(),
                      [&](std::size_t k) { left_out[k] = predict_left_out(model, fit, k, options, say_locked); });
    for (std::size_t k = 0; k < targets.size(); ++k) loo.emplace(targets[k]->id, std::move(left_out[k]));
}

}  // namespace

FitReport fit_targets(const CalibrationModel& model, const FitOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const std::function<void(const std::string&)> say = [&](const std::string& line) {
        if (options.progress) options.progress(line);
    };
    FitReport report;
    report.targets_name = model.targets().name;
    std::map<std::string, std::vector<const Target*>> fitted_by_machine;
    std::set<std::string> machines;
    for (const Target& t : model.targets().targets) {
        if (t.is_formula()) continue;  // nothing to fit
        machines.insert(t.machine);
        if (t.fitted()) fitted_by_machine[t.machine].push_back(&t);
    }
    std::map<std::string, TargetResult> loo;
    for (const std::string& machine : machines) {
        const CalibrationScales start = CalibrationScales::from(model.base_config(machine));
        std::vector<FittedParameter> params = initial_parameters(machine, model.base_config(machine), start, true);
        const std::vector<const Target*>& targets = fitted_by_machine[machine];
        if (targets.empty()) {
            for (FittedParameter& p : params) {
                p.free = false;
                p.note = "no fitted target runs on this machine; held at the machine file's value";
            }
            report.parameters.insert(report.parameters.end(), params.begin(), params.end());
            continue;
        }
        say(fmt::format("{}: measuring what each scale moves ({} fitted targets)", machine, targets.size()));
        const fit_detail::ScaleResponse response = fit_detail::measure_scale_response(model, machine, targets, start);
        const std::vector<int> free = fit_detail::choose_free_scales(response, params, targets.size(), machine,
                                                                     model.targets().file.string(), report.notes);
        if (!free.empty()) {
            const auto fit = fit_machine(model, machine, targets, start, free, bounds_of(model.base_config(machine)),
                                         options, params, report, say);
            if (options.leave_one_out) leave_each_out(model, *fit, targets, options, say, loo);
        }
        report.parameters.insert(report.parameters.end(), params.begin(), params.end());
    }
    for (const auto& [id, r] : loo) report.results.push_back(r);
    evaluate_all(model, report);
    add_fit_intervals(model, report);
    // The uncalibrated value beside each fitted one: what the documented costs alone give.
    const FitReport given = evaluate_targets(model, {});
    for (std::size_t i = 0; i < report.results.size() && i < given.results.size(); ++i)
        report.results[i].uncalibrated = given.results[i].simulated;
    report.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return report;
}

}  // namespace pp5
