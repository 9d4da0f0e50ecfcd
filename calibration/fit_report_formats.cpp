// A fit's report as JSON (fit.json) and as Markdown (fit.md).
#include "calibration/fit.h"

#include "calibration/fit_detail.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace pp5 {

using fit_detail::number;
using fit_detail::percent;

namespace {

nlohmann::json nan_to_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

template <class T>
nlohmann::json or_null(const std::optional<T>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

// One row of fit.json: the target, what the fit made of it, and its intervals (null where none).
nlohmann::json row_json(const FitReport& report, const TargetResult& r) {
    nlohmann::json row{{"id", r.target.id},
                       {"source", r.target.source},
                       {"quote", r.target.quote},
                       {"scenario", r.target.scenario},
                       {"frame", r.target.frame},
                       {"machine", r.target.machine},
                       {"metric", r.target.metric},
                       {"divided_by_frame", r.target.divided_by_frame >= 0 ? nlohmann::json(r.target.divided_by_frame)
                                                                           : nlohmann::json(nullptr)},
                       {"unit", r.target.unit},
                       {"reported", r.target.reported},
                       {"exactness", std::string(to_string(r.target.exactness))},
                       {"simulated", r.simulated},
                       {"relative_error", r.relative_error},
                       {"use", std::string(to_string(r.target.use))},
                       {"group", std::string(to_string(report.group_of(r.target)))},
                       {"used_by_workload_step", report.used_by_workload(r.target)}};
    if (r.target.is_formula()) {
        row["kernel"] = r.target.kernel;
        row["formula"] = r.target.formula;
        row["inputs"] = r.target.inputs;
        for (const char* unused : {"scenario", "frame", "machine", "metric", "divided_by_frame"}) row.erase(unused);
    }
    row["uncalibrated"] = or_null(r.uncalibrated);
    row["uncalibrated_low"] = or_null(r.plausible_low);
    row["uncalibrated_high"] = or_null(r.plausible_high);
    row["simulated_low"] = or_null(r.low);
    row["simulated_high"] = or_null(r.high);
    row["leave_one_out"] = or_null(r.leave_one_out);
    row["leave_one_out_error"] = or_null(r.leave_one_out_error);
    if (!r.leave_one_out_note.empty()) row["leave_one_out_note"] = r.leave_one_out_note;
    return row;
}

nlohmann::json summary_json(const ErrorSummary& s) {
    return nlohmann::json{{"count", s.count},
                          {"mean_absolute_relative_error", s.mean_absolute_error},
                          {"max_absolute_relative_error", s.max_absolute_error},
                          {"within_10_percent", s.within_10},
                          {"within_25_percent", s.within_25},
                          {"log_correlation", nan_to_null(s.log_correlation)}};
}

}  // namespace

nlohmann::json FitReport::to_json() const {
    nlohmann::json params = nlohmann::json::array();
    for (const FittedParameter& p : parameters) {
        params.push_back({{"machine", p.machine},
                          {"key", p.key},
                          {"value", p.value},
                          {"standard_error", nan_to_null(p.standard_error)},
                          {"lower", p.lower},
                          {"upper", p.upper},
                          {"free", p.free},
                          {"at_bound", p.at_bound},
                          {"provenance", p.provenance},
                          {"note", p.note}});
    }
    nlohmann::json rows = nlohmann::json::array();
    for (const TargetResult& r : results) rows.push_back(row_json(*this, r));
    nlohmann::json identified = nlohmann::json::array();
    for (const IdentifiedWorkload& w : workload) {
        identified.push_back({{"parameter", w.spec.key},
                              {"value", w.value},
                              {"machine_file_value", format_param_value(w.machine_value)},
                              {"bounds", {w.spec.lower, w.spec.upper}},
                              {"ratio_of", {w.spec.numerator, w.spec.denominator}},
                              {"reported_ratio", w.reported_ratio},
                              {"simulated_ratio", w.simulated_ratio},
                              {"trials", w.trials},
                              {"at_bound", w.at_bound},
                              {"why", w.spec.why},
                              {"note", w.note}});
    }
    return {{"targets", targets_name},
            {"workload", identified},
            {"parameters", params},
            {"rows", rows},
            {"summary",
             [&] {
                 // Each group apart: only "predicted" holds predictions (see RowGroup).
                 nlohmann::json groups = nlohmann::json::object();
                 for (const RowGroup g : kRowGroups) groups[std::string(to_string(g))] = summary_json(summary(g));
                 nlohmann::json units = nlohmann::json::object();
                 for (const auto& [unit, s] : by_unit()) units[unit] = summary_json(s);
                 groups["by_unit"] = units;
                 return groups;
             }()},
            {"degrees_of_freedom",
             [&] {
                 nlohmann::json machines = nlohmann::json::array();
                 for (const MachineFreedom& f : freedom)
                     machines.push_back({{"machine", f.machine},
                                         {"fitted_rows", f.rows},
                                         {"free_scales", f.free_scales},
                                         {"workload_parameters", f.workload_parameters},
                                         {"degrees_of_freedom", f.degrees_of_freedom()},
                                         {"reduced_chi_square", nan_to_null(f.reduced_chi_square)}});
                 return machines;
             }()},
            {"notes", notes},
            {"host_seconds", host_seconds}};
}

namespace {

// The workload step: the parameters identified before the fit, from ratios of measured rows.
void write_workload_step(const FitReport& report, std::ostringstream& md) {
    if (!report.workload.empty()) {
        md << "## Workload step\n\nParameters the paper does not give, identified before the fit from the ratio of two "
              "measured rows on "
              "one machine (its speed cancels). The fit and every row below use these values.\n\n"
           << "| parameter | identified | machine file | from the ratio | reported | simulated | trials | why "
              "|\n|---|---|---|---|---|---|---|---|\n";
        for (const IdentifiedWorkload& w : report.workload) {
            md << fmt::format("| `{}` | {:.4g}{} | {} | {} / {} | {:.4g} | {:.4g} | {} | {}{} |\n", w.spec.key, w.value,
                              w.at_bound ? " (at bound)" : "", format_param_value(w.machine_value), w.spec.numerator,
                              w.spec.denominator, w.reported_ratio, w.simulated_ratio, w.trials, w.spec.why,
                              w.note.empty() ? "" : " *" + w.note + "*");
        }
        md << "\n";
    }
}

// The fitted scales, their standard errors and where their bounds come from.
void write_parameters(const FitReport& report, std::ostringstream& md) {
    md << "## Parameters\n\n"
       << "| machine | parameter | value | standard error | bounds | status |\n|---|---|---|---|---|---|\n";
    for (const FittedParameter& p : report.parameters) {
        md << fmt::format("| {} | `{}` | {:.4g} | {} | [{:g}, {:g}] | {} |\n", p.machine, p.key, p.value,
                          number(p.standard_error), p.lower, p.upper,
                          p.free ? (p.note.empty() ? "fitted" : "fitted; " + p.note) : p.note);
    }
    md << "\nWhere each fitted scale's bounds come from (the machine file's `<scale>_bounds_why`):\n\n";
    for (const FittedParameter& p : report.parameters)
        if (p.free) md << fmt::format("- {} `{}` [{:g}, {:g}]: {}\n", p.machine, p.key, p.lower, p.upper, p.provenance);
}

// Every row: reported, uncalibrated and simulated with their intervals, its use, its leave-one-out prediction.
void write_targets(const FitReport& report, std::ostringstream& md) {
    const bool any_uncalibrated = std::any_of(report.results.begin(), report.results.end(),
                                              [](const TargetResult& r) { return r.uncalibrated.has_value(); });
    md << "\n## Targets\n\n";
    if (std::any_of(report.results.begin(), report.results.end(),
                    [](const TargetResult& r) { return r.low.has_value(); }))
        md << "Intervals on simulated values cover the fitted scales' uncertainty (their covariance, linearised by "
              "re-timing).";
    if (std::any_of(report.results.begin(), report.results.end(),
                    [](const TargetResult& r) { return r.plausible_low.has_value(); }))
        md << " Intervals on uncalibrated values cover the documented guesses' plausible ranges (`pp5sim params`), "
              "each spread "
              "evenly over its range, at the processor rates the machine file states (the rates are what the fit's "
              "scales measure).";
    md << "\n\n";
    md << "| id | machine | metric | reported | " << (any_uncalibrated ? "uncalibrated | " : "")
       << "simulated [95% interval from the fit] | error | use | leave-one-out prediction |\n"
       << (any_uncalibrated ? "|---|---|---|---|---|---|---|---|---|\n" : "|---|---|---|---|---|---|---|---|\n");
    for (const TargetResult& r : report.results) {
        std::string loo =
            r.leave_one_out ? fmt::format("{} ({})", number(*r.leave_one_out), percent(*r.leave_one_out_error)) : "";
        if (!r.leave_one_out_note.empty()) loo += (loo.empty() ? "" : "; ") + r.leave_one_out_note;
        const std::string unit = r.target.divided_by_frame >= 0
                                     ? fmt::format("frame {} / frame {}", r.target.frame, r.target.divided_by_frame)
                                     : r.target.unit;
        const bool formula = r.target.is_formula();
        const std::string uncalibrated =
            !any_uncalibrated ? ""
            : r.uncalibrated
                ? fmt::format("{}{} ({}) | ", number(*r.uncalibrated),
                              r.plausible_low && r.plausible_high
                                  ? fmt::format(" [{}, {}]", number(*r.plausible_low), number(*r.plausible_high))
                                  : std::string(),
                              percent((*r.uncalibrated - r.target.reported) / r.target.reported))
                : " | ";
        md << fmt::format("| {} | {} | {} ({}) | {} | {}{} | {} | {} | {} |\n", r.target.id,
                          formula ? "(formula: " + r.target.kernel + ")" : r.target.machine,
                          formula ? r.target.formula : r.target.metric, unit, number(r.target.reported), uncalibrated,
                          r.low && r.high
                              ? fmt::format("{} [{}, {}]", number(r.simulated), number(*r.low), number(*r.high))
                              : number(r.simulated),
                          percent(r.relative_error), describe(report.group_of(r.target)), loo);
    }
    std::size_t banded = 0, inside = 0;
    for (const TargetResult& r : report.results)
        if (r.plausible_low && r.plausible_high) {
            ++banded;
            inside += r.target.reported >= *r.plausible_low && r.target.reported <= *r.plausible_high;
        }
    if (banded > 0)
        md << fmt::format(
            "\nThe reported figure lies within the uncalibrated interval for {} of {} simulated rows. Where it does "
            "not, the "
            "documented guesses alone cannot account for the difference: the processors' rates (the fit's to find) or "
            "work the model leaves out must.\n",
            inside, banded);
}

// Each kind of row's errors apart, each machine's degrees of freedom, errors by unit.
void write_fit_quality(const FitReport& report, std::ostringstream& md) {
    md << "\n## Fit quality\n\nEach kind of row apart: only the predicted rows test the model on figures it never saw. "
          "Rows the "
          "workload step matched have spent their freedom on its parameters; arithmetic checks, "
          "rows matched by "
          "construction and "
          "comparisons with another machine test something else.\n\n"
       << "| rows | count | mean abs. error | max abs. error | within 10% | within 25% | r (log) |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const RowGroup group : kRowGroups) {
        const ErrorSummary s = report.summary(group);
        if (s.count == 0) continue;
        md << fmt::format("| {} | {} | {:.1f}% | {:.1f}% | {} | {} | {} |\n", describe(group), s.count,
                          100.0 * s.mean_absolute_error, 100.0 * s.max_absolute_error, s.within_10, s.within_25,
                          number(s.log_correlation));
    }
    if (!report.freedom.empty()) {
        md << "\n| machine | fitted rows | free scales | workload parameters | degrees of freedom "
              "| reduced chi-square "
              "|\n|---|---|---|---|---|---|\n";
        for (const MachineFreedom& f : report.freedom)
            md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", f.machine, f.rows, f.free_scales,
                              f.workload_parameters, f.degrees_of_freedom(), number(f.reduced_chi_square));
    }
    const auto units = report.by_unit();
    if (units.size() > 1) {
        md << "\nBy the metric's unit (fitted, workload and predicted rows together):\n\n| unit | count | mean "
              "abs. "
              "error | max abs. error | within 10% | within 25% |\n"
           << "|---|---|---|---|---|---|\n";
        for (const auto& [unit, s] : units)
            md << fmt::format("| {} | {} | {:.1f}% | {:.1f}% | {} | {} |\n", unit, s.count,
                              100.0 * s.mean_absolute_error, 100.0 * s.max_absolute_error, s.within_10, s.within_25);
    }
}

// Rows more than 25% off, then the solver's notes.
void write_outliers_and_solver(const FitReport& report, std::ostringstream& md) {
    md << "\n## Outliers (more than 25% off)\n\n";
    bool any = false;
    for (const TargetResult& r : report.results) {
        if (std::abs(r.relative_error) <= 0.25) continue;
        any = true;
        md << fmt::format("- `{}` ({}): reported {} {}, simulated {} ({})\n", r.target.id,
                          describe(report.group_of(r.target)), number(r.target.reported), r.target.unit,
                          number(r.simulated), percent(r.relative_error));
    }
    if (!any) md << "None.\n";
    if (!report.notes.empty()) {
        md << "\n## Solver\n\n";
        for (const std::string& n : report.notes) md << "- " << n << "\n";
    }
}

}  // namespace

std::string FitReport::to_markdown() const {
    std::ostringstream md;
    md << "# Calibration against " << targets_name << "\n\n";
    write_workload_step(*this, md);
    write_parameters(*this, md);
    write_targets(*this, md);
    write_fit_quality(*this, md);
    write_outliers_and_solver(*this, md);
    return md.str();
}

}  // namespace pp5
