// A machine file with a fit's scales written into its [calibration] table.
#include "calibration/fit.h"

#include "calibration/fit_detail.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace pp5 {

using fit_detail::kScales;
using fit_detail::number;
using fit_detail::ScaleSpec;

namespace {

std::string trim(const std::string& t) {
    const auto b = t.find_first_not_of(" \t");
    const auto e = t.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : t.substr(b, e - b + 1);
}

// The key of a "key = value" line with its comment removed.
std::string key_of(const std::string& bare) { return trim(bare.substr(0, bare.find('='))); }

// The file's own header first: what it is and how well it fits, before the preset's description.
std::string fitted_header(const CalibrationModel& model, const FitReport& report, const std::string& machine) {
    const std::string stem = std::filesystem::path(machine).stem().string();
    const ErrorSummary fitted = report.summary(RowGroup::Fitted);
    const ErrorSummary workload_rows = report.summary(RowGroup::Workload);
    const ErrorSummary predicted = report.summary(RowGroup::Predicted);
    return fmt::format(
               "# {}-fitted: the {} machine with its calibration.* scales fitted by `pp5sim fit` to the targets of "
               "{}\n",
               stem, stem, model.targets().file.string()) +
           fmt::format(
               "# ({}). Targets within 10%: {} of {} fitted, {} of {} workload rows, {} of {} predicted; mean "
               "error {:.1f}% fitted, {:.1f}% predicted.\n",
               model.targets().name, fitted.within_10, fitted.count, workload_rows.within_10, workload_rows.count,
               predicted.within_10, predicted.count, 100.0 * fitted.mean_absolute_error,
               100.0 * predicted.mean_absolute_error) +
           "# The fit's report (fit.md, fit.json) is beside this file; below are the preset as it was and the "
           "fitted\n# [calibration] table. Use it with: pp5sim render --machine <this file>\n\n";
}

// The workload step's values, by table ("levoy.refinement_threshold" goes in [levoy]): (name, line).
using WorkloadSettings = std::map<std::string, std::vector<std::pair<std::string, std::string>>>;

WorkloadSettings workload_settings(const FitReport& report) {
    WorkloadSettings settings;
    for (const IdentifiedWorkload& w : report.workload) {
        const auto dot = w.spec.key.rfind('.');
        const std::string name = w.spec.key.substr(dot + 1);
        settings[w.spec.key.substr(0, dot)].emplace_back(
            name,
            fmt::format("{} = {}    # identified by the workload step from {} / {} (the file had {})", name,
                        w.spec.integer ? fmt::format("{}", std::llround(w.value)) : fmt::format("{:.6g}", w.value),
                        w.spec.numerator, w.spec.denominator, format_param_value(w.machine_value)));
    }
    return settings;
}

// Copies the preset line by line with the machine renamed, the workload step's values in place of the
// preset's own lines, and its [calibration] table left out: returns that table's lines other than the
// scales (their bounds and sources), which carry over.
std::vector<std::string> copy_preset(std::istream& text, const WorkloadSettings& workload, std::ostream& out,
                                     std::set<std::string>& tables_written) {
    std::vector<std::string> kept_calibration_lines;
    std::string line;
    std::string table;
    while (std::getline(text, line)) {
        const std::string bare = trim(line.substr(0, line.find('#')));
        if (bare.size() > 2 && bare.front() == '[' && bare.back() == ']' && bare[1] != '[') {
            table = trim(bare.substr(1, bare.size() - 2));
            if (table == "calibration") continue;  // one [calibration] table, written after with the fitted values
            if (const auto it = workload.find(table); it != workload.end()) {
                out << line << "\n";
                for (const auto& [name, setting] : it->second) out << setting << "\n";
                tables_written.insert(table);
                continue;
            }
        }
        if (table == "calibration") {
            const std::string key = key_of(bare);
            const bool scale = std::any_of(std::begin(kScales), std::end(kScales),
                                           [&](const ScaleSpec& spec) { return key == spec.name; });
            if (!bare.empty() && !scale) kept_calibration_lines.push_back(line);
            continue;
        }
        if (const auto it = workload.find(table); it != workload.end()) {
            const std::string key = key_of(bare);
            if (std::any_of(it->second.begin(), it->second.end(),
                            [&](const auto& entry) { return entry.first == key; }))
                continue;
        }
        if (table == "machine" && bare.rfind("name", 0) == 0 && trim(bare.substr(4)).rfind("=", 0) == 0) {
            const auto close = line.find('"', line.find('"') + 1);
            if (close != std::string::npos) line.insert(close, "-fitted");
        }
        out << line << "\n";
    }
    return kept_calibration_lines;
}

}  // namespace

std::string fitted_machine_file(const CalibrationModel& model, const FitReport& report, const std::string& machine) {
    std::ifstream in(resolve_machine_file(machine));
    std::ostringstream out;
    out << fitted_header(model, report, machine);
    const WorkloadSettings workload = workload_settings(report);
    std::set<std::string> tables_written;
    const std::vector<std::string> kept_calibration_lines = copy_preset(in, workload, out, tables_written);
    for (const auto& [name, lines] : workload) {
        if (tables_written.count(name)) continue;  // written under the preset's own header
        out << "\n[" << name << "]\n";
        for (const auto& [key, setting] : lines) out << setting << "\n";
    }
    out << "\n[calibration]                 # fitted by `pp5sim fit` to " << model.targets().name
        << "; standard errors in comments\n";
    for (const FittedParameter& p : report.parameters) {
        if (p.machine != machine) continue;
        const std::string key = p.key.substr(std::string("calibration.").size());
        std::string comment = p.free ? fmt::format("+/- {}", number(p.standard_error)) : "held: " + p.note;
        if (p.at_bound) comment += " (at its bound)";
        out << fmt::format("{} = {:.6g}    # {}\n", key, p.value, comment);
    }
    for (const std::string& kept : kept_calibration_lines) out << kept << "\n";
    return out.str();
}

}  // namespace pp5
