#pragma once
// The calibration's free parameters ("calibration.*"): a few scale factors, each over a whole family of
// documented per-operation costs, so that a fit moves the model as a whole and never one cost per
// target. 1 leaves the documented costs as they are; `pp5sim fit` writes the fitted values into a
// machine file with their standard errors.

#include "sim/core/config.h"
#include "sim/core/param.h"

#include <string>

namespace pp5 {

struct CalibrationScales {
    double gp_flops = 1.0;   // every GP cost in flops (gp_cost.*, every kernel's included)
    double gp_cycles = 1.0;  // every GP cost in cycles
    double pp_cycles = 1.0;  // every PP program's cycles: ALU, controller and backing store

    static const ParamGroup& params();
    static CalibrationScales from(const MachineConfig& config);
};

// The range a fit may move one scale in, and why: what the machine could physically do, from its
// machine file (calibration.<scale>_min, <scale>_max and <scale>_bounds_why). `scale` is
// "gp_flops_scale", "gp_cycles_scale" or "pp_cycles_scale". Throws InputError when min >= max.
struct ScaleBounds {
    double lower = 0.0;
    double upper = 0.0;
    std::string why;
};
ScaleBounds scale_bounds(const MachineConfig& config, const std::string& scale);

// The calibration in force, for stats.json's timing model: "documented costs, uncalibrated (every
// calibration scale 1)", or the scales that differ from 1 and where each was set.
std::string describe_calibration(const MachineConfig& config);

}  // namespace pp5
