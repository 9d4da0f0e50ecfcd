#pragma once
// Why a row misses its paper's figure, computed from the run so that it stays true when the model
// changes: where the simulated time goes (each phase, the work it did, the PP cycles a voxel slot
// costs), what the figure would need instead, how the row stands against the other frames the paper
// timed with it (a light change against an observer move), the paper's own assumption when the target
// file quotes it, and a what-if: the one documented parameter change that would reconcile the row,
// found by re-timing (sensitivity.h), with what it would do to the machine's other rows.

#include "calibration/fit.h"
#include "calibration/sensitivity.h"

#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pp5 {

struct PhaseAccount {
    std::string name;
    double seconds = 0.0;
    std::vector<std::pair<std::string, double>> work;  // what it did: operations by kind, fetches, cycles per slot...
};

// The row against another row of the same scenario, machine and metric at another frame.
struct FrameComparison {
    std::string other;            // its id
    double reported_ratio = 0.0;  // this row's reported value over the other's
    double simulated_ratio = 0.0;
    std::vector<std::pair<std::string, std::pair<double, double>>> phase_seconds;  // phase -> (this frame, the other)
};

struct ResidualAccount {
    std::string id;
    double reported = 0.0;
    double relative_error = 0.0;
    double needed_factor = 1.0;        // reported over simulated: what the figure asks of the simulated value
    std::vector<PhaseAccount> phases;  // the row's frame on its machine (not for ratio rows)
    std::vector<FrameComparison> against;
    std::string assumption;  // the paper's, when the target file quotes it (Target::assumes)
    std::optional<WhatIf> what_if;
    std::vector<std::string> other_rows;  // ids, in WhatIf::others' order
    std::vector<double> other_reported;
    std::vector<double> before;  // the machine's rows as simulated, in the same order
};

// Every simulated row more than `threshold` off (relative), at the report's scales.
std::vector<ResidualAccount> explain_residuals(const CalibrationModel& model, const FitReport& report,
                                               double threshold = 0.10);

std::string residuals_markdown(const std::vector<ResidualAccount>& accounts);
nlohmann::json residuals_json(const std::vector<ResidualAccount>& accounts);

}  // namespace pp5
