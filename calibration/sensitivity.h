#pragma once
// How a machine's simulated rows respond to each of its documented timing parameters: the elasticity
// d ln(simulated) / d ln(parameter), measured by re-timing the recorded work with the parameter moved,
// as the fit re-times it (timing_model.h). One table serves the what-ifs of the reproduction report
// (which single change would reconcile a row, and what it would do to the others).

#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "sim/core/calibration.h"

#include <optional>
#include <string>
#include <vector>

namespace pp5 {

struct ParameterElasticity {
    std::string key;
    double value = 0.0;  // in the machine's configuration
    bool integer = false;
    std::optional<double> lower, upper;  // the parameter's declared range
    std::vector<double> elasticity;      // one per row, in MachineSensitivity::rows' order
};

struct MachineSensitivity {
    std::string machine;
    CalibrationScales scales;  // applied throughout (fitted or given)
    std::vector<const Target*> rows;
    std::vector<double> simulated;                // each row at the configuration
    std::vector<ParameterElasticity> parameters;  // only those that move some row
};

// Every numeric timing parameter of `machine` but the calibration's own scales (the fit's to move),
// each moved up by 10% (a whole step at least, for a count), the runs side by side.
MachineSensitivity measure_sensitivity(const CalibrationModel& model, const std::string& machine,
                                       const CalibrationScales& scales, std::vector<const Target*> rows);

// One documented parameter moved until a row matches its reported value.
struct WhatIf {
    std::string key;
    double from = 0.0;
    double to = 0.0;
    bool within_range = true;    // `to` inside the parameter's declared range (else held at its edge)
    double reached = 0.0;        // the row's simulated value with the change
    std::vector<double> others;  // every row's simulated value with the change (MachineSensitivity::rows' order)
};

// The change of one parameter that reconciles row `row` while moving the machine's other rows least
// (by the elasticities), refined by re-timing; nullopt when no parameter moves the row.
std::optional<WhatIf> reconcile(const CalibrationModel& model, const MachineSensitivity& sensitivity, std::size_t row);

}  // namespace pp5
