#include "sim/core/calibration.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <vector>

namespace pp5 {

namespace {

// Each family's default range is Pixel-planes 5's, like every other default; a machine file for other
// hardware gives its own (sun4-280.toml does).
struct ScaleFamily {
    const char* name;
    const char* doc;
    double min;
    double max;
    const char* why;
};
constexpr ScaleFamily kFamilies[] = {
    {"gp_flops_scale", "Multiplies every graphics-processor cost counted in flops (gp_cost.*, every kernel's included)",
     0.5, 10.0,
     "flops are counted at Levoy's 20 MFLOPS: 0.5 is 40 MFLOPS, about the best hand-coded i860 assembly reached (the "
     "40 MHz part "
     "peaks at 80); 10 is 2 MFLOPS, compiled code no faster than two Sun 4/280s (1.1 MFLOPS each), where i860 "
     "compilers seldom "
     "passed 10 MFLOPS"},
    {"gp_cycles_scale",
     "Multiplies every graphics-processor cost counted in cycles (gp_cost.*, every kernel's included)", 0.5, 4.0,
     "cycles are counted at the i860's 40 MHz: 0.5 is dual-instruction mode issuing a core and a floating-point "
     "instruction "
     "together (Intel i860 data sheet); 4 is control code stalling about three cycles an instruction on its 8 KB data "
     "cache (ours)"},
    {"pp_cycles_scale", "Multiplies the cycles of every pixel-processor program: ALU, controller and backing store",
     1.0, 4.0,
     "PP cycles are counted at the 40 MHz the chips were designed for (Fuchs et al. 1989): a bit-serial ALU cannot do "
     "better than "
     "an operand bit a cycle, so no lower than 1; 4 leaves room for what the counts omit (issue stalls, backing-store "
     "contention, a "
     "clock below design), beyond which the counts, not the machine, would be wrong (ours)"},
};

}  // namespace

const ParamGroup& CalibrationScales::params() {
    static const ParamGroup group = [] {
        ParamGroup g("calibration",
                     "Scale factors over families of documented costs; 1 = uncalibrated, `pp5sim fit` sets them");
        g.all_timing_only();  // it changes when work happens, never what is computed
        const char* source =
            "1 (uncalibrated); a fitted machine file gives the value `pp5sim fit` found, with its standard error";
        for (const ScaleFamily& family : kFamilies) {
            const std::string name = family.name;
            g.real(name, 1.0, "factor", 1e-3, 1e3, family.doc, Provenance::Default, source)
                .real(name + "_min", family.min, "factor", 1e-3, 1e3,
                      "The lowest value `pp5sim fit` may give " + name +
                          ": the fastest this machine could physically run that cost family",
                      Provenance::Hardware, family.why)
                .real(name + "_max", family.max, "factor", 1e-3, 1e3,
                      "The highest value `pp5sim fit` may give " + name +
                          ": the slowest that is still this machine with these counts",
                      Provenance::Hardware, family.why)
                .text(name + "_bounds_why", family.why, {},
                      "Where " + name +
                          "'s range comes from (data sheets, papers); the fit report quotes it, above all for a scale "
                          "at a bound",
                      Provenance::Hardware, "Pixel-planes 5's; a machine file for other hardware gives its own");
        }
        return g;
    }();
    return group;
}

ScaleBounds scale_bounds(const MachineConfig& config, const std::string& scale) {
    const std::string key = "calibration." + scale;
    ScaleBounds bounds{config.real(key + "_min"), config.real(key + "_max"), config.text(key + "_bounds_why")};
    if (!(bounds.lower < bounds.upper))
        throw InputError(config.origin(key + "_min"), key + "_min",
                         fmt::format("must be below {}_max ({:g}), but is {:g}", key, bounds.upper, bounds.lower));
    return bounds;
}

CalibrationScales CalibrationScales::from(const MachineConfig& config) {
    return CalibrationScales{config.real("calibration.gp_flops_scale"), config.real("calibration.gp_cycles_scale"),
                             config.real("calibration.pp_cycles_scale")};
}

std::string describe_calibration(const MachineConfig& config) {
    std::vector<std::string> scaled;
    for (const ScaleFamily& family : kFamilies) {
        const std::string key = std::string("calibration.") + family.name;
        const double value = config.real(key);
        if (value != 1.0) scaled.push_back(fmt::format("{} = {:.6g} (from {})", key, value, config.origin(key)));
    }
    if (scaled.empty()) return "documented costs, uncalibrated (every calibration scale 1)";
    return fmt::format("documented costs scaled by {}", fmt::join(scaled, ", "));
}

}  // namespace pp5
