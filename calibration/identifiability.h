#pragma once
// Which calibration scales a machine's fitted targets can tell apart (internal to calibration/): each
// scale's elasticity on every target is measured by simulation, and a scale is held at its machine
// file's value, with a note saying why, when it moves no target enough, when the targets respond to it
// and to a stronger one alike, or when freeing it would leave a scale pinned by a single figure.

#include "calibration/fit.h"
#include "calibration/fit_detail.h"

#include <string>
#include <vector>

namespace pp5::fit_detail {

// How each scale moves the fitted targets, from a 10% step of each in turn.
struct ScaleResponse {
    // Per scale, the elasticity (d ln figure / d ln scale) on each target in units of that target's
    // stated uncertainty, and the largest unweighted elasticity on any target.
    std::vector<std::vector<double>> columns;
    std::vector<double> max_elasticity;

    double strength(int scale) const;           // the column's length
    double cosine(int scale, int other) const;  // how alike two scales move the targets
};

ScaleResponse measure_scale_response(const CalibrationModel& model, const std::string& machine,
                                     const std::vector<const Target*>& targets, const CalibrationScales& start);

// The scales to fit, in kScales order; every other one in `params` is held with its note. Notes on
// nearly alike pairs go to `notes`. Throws InputError (naming `targets_file`) when the machine has too
// few fitted targets to free any scale.
std::vector<int> choose_free_scales(const ScaleResponse& response, std::vector<FittedParameter>& params,
                                    std::size_t target_count, const std::string& machine,
                                    const std::string& targets_file, std::vector<std::string>& notes);

}  // namespace pp5::fit_detail
