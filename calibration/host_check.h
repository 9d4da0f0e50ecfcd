#pragma once
// The model checked against a real machine, this one. pp5sim's reference renderer (scene/reference)
// is timed on a set of cases (volumes, image sizes, transfer functions), one thread, best of a few
// runs. The cost model that times the GPs (on the `host` preset's rates) prices each case's counted
// work: a ray's setup per ray; a sample's step, interpolation and compositing per sample (flops,
// gp_cost.reference.*, whose defaults are Levoy's ray caster's counts); and, as a GP pays to copy each received word
// into its cache, each voxel of the volume brought through the host's memory hierarchy once a frame (cycles; a small
// image of a large volume touches as much memory as a large one). Skipped empty space is left unpriced: the reference
// renderer leaps whole empty blocks. Ceres fits the host's two scales (flops and cycles) to half the
// cases; the other half are predicted and their errors reported.

#include "sim/core/config.h"

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <string>
#include <vector>

namespace pp5 {

struct HostCase {
    std::string scenario;
    int image_size = 256;
    bool fitted = true;
    // Counted work of one frame, and its measured time.
    std::uint64_t rays = 0;
    std::uint64_t samples = 0;
    std::uint64_t samples_skipped = 0;
    std::uint64_t voxels = 0;
    double measured_seconds = 0.0;
    // The model: flop and cycle parts at scale 1, and the prediction at the fitted scales.
    double flop_seconds = 0.0;
    double cycle_seconds = 0.0;
    double predicted_seconds = 0.0;
    double relative_error() const { return (predicted_seconds - measured_seconds) / measured_seconds; }
};

struct HostCheckReport {
    std::vector<HostCase> cases;
    double gp_flops_scale = 1.0;
    double gp_cycles_scale = 1.0;
    double gp_flops_standard_error = 0.0;
    double gp_cycles_standard_error = 0.0;
    double median_fitted_error = 0.0;    // absolute, relative
    double median_held_out_error = 0.0;  // absolute, relative
    double max_held_out_error = 0.0;
    std::string solver;

    nlohmann::json to_json() const;
    std::string to_markdown() const;
};

struct HostCheckOptions {
    // Scenario names and square image sizes; every combination is a case, alternately fitted and
    // held out.
    std::vector<std::string> scenarios{"sphere", "head-phantom", "mr-head", "ct-head"};
    std::vector<int> image_sizes{128, 256, 384, 512};
    int repeats = 3;  // best of
    std::function<void(const std::string&)> progress;
};

HostCheckReport run_host_check(const MachineConfig& host, const HostCheckOptions& options);

// The fit alone: from the cases' measured times and model parts, the two scales, the predictions and
// the error summary.
void fit_host_cases(HostCheckReport& report);

}  // namespace pp5
