#pragma once
// What fit.cpp and the files that choose a fit's free scales (identifiability.cpp), write its report,
// its fitted machine and the account of each row that misses (residuals.cpp) share: the scales a fit
// can move, and how its numbers are written. Internal to calibration/.

#include "calibration/timing_model.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <string>

namespace pp5::fit_detail {

struct ScaleSpec {
    const char* name;  // as in the machine file's [calibration]
    double CalibrationScales::*member;
};
// Each scale's bounds are its machine's (calibration.<name>_min and _max): what that hardware could
// physically do, with the source in <name>_bounds_why.
inline constexpr ScaleSpec kScales[] = {
    {"gp_flops_scale", &CalibrationScales::gp_flops},
    {"gp_cycles_scale", &CalibrationScales::gp_cycles},
    {"pp_cycles_scale", &CalibrationScales::pp_cycles},
};
inline constexpr int kScaleCount = static_cast<int>(std::size(kScales));
// The scale's key among the machine's parameters.
inline std::string key_of(const ScaleSpec& spec) { return std::string("calibration.") + spec.name; }

// A relative difference as a signed percentage, one decimal: "+12.5%".
inline std::string percent(double relative) { return fmt::format("{:+.1f}%", 100.0 * relative); }

// Four significant digits, or "n/a" for a value that is not finite.
inline std::string number(double v) {
    if (!std::isfinite(v)) return "n/a";
    return fmt::format("{:.4g}", v);
}

}  // namespace pp5::fit_detail
