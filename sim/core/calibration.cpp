#include "sim/core/calibration.h"

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

}  // namespace pp5
