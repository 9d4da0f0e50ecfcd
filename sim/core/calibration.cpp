#include "sim/core/calibration.h"

#include <fmt/format.h>

#include <vector>

namespace pp5 {

const ParamGroup& CalibrationScales::params() {
    static const ParamGroup group = [] {
        ParamGroup g("calibration", "Scale factors over families of documented costs; 1 = uncalibrated, `pp5sim fit` sets them");
        const char* source = "1 (uncalibrated); a fitted machine file gives the value `pp5sim fit` found, with its standard error";
        g.real("gp_flops_scale", 1.0, "factor", 1e-3, 1e3, "Multiplies every graphics-processor cost counted in flops (gp_cost.*, every kernel's included)",
               Provenance::Default, source)
            .real("gp_cycles_scale", 1.0, "factor", 1e-3, 1e3,
                  "Multiplies every graphics-processor cost counted in cycles (gp_cost.*, every kernel's included)", Provenance::Default, source)
            .real("pp_cycles_scale", 1.0, "factor", 1e-3, 1e3,
                  "Multiplies the cycles of every pixel-processor program: ALU, controller and backing store", Provenance::Default,
                  source);
        return g;
    }();
    return group;
}

CalibrationScales CalibrationScales::from(const MachineConfig& config) {
    return CalibrationScales{config.real("calibration.gp_flops_scale"), config.real("calibration.gp_cycles_scale"),
                             config.real("calibration.pp_cycles_scale")};
}

std::string describe_calibration(const MachineConfig& config) {
    std::vector<std::string> scaled;
    for (const ParamSpec& spec : CalibrationScales::params().specs()) {
        const std::string key = "calibration." + spec.name;
        const double value = config.real(key);
        if (value != 1.0) scaled.push_back(fmt::format("{} = {:.6g} (from {})", key, value, config.origin(key)));
    }
    if (scaled.empty()) return "documented costs, uncalibrated (every calibration scale 1)";
    return fmt::format("documented costs scaled by {}", fmt::join(scaled, ", "));
}

}  // namespace pp5
