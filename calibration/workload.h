#pragma once
// The workload step, before any scale is fitted: each [[workload]] parameter of a target file (what a
// kernel computes that the paper leaves unsaid, such as Levoy's refinement threshold) is searched for
// within its bounds until the ratio of its two measured rows, simulated at their machine's own scales,
// equals the reported ratio. The machine's speed cancels in the ratio, so no scale is involved; the
// scales are fitted afterwards on the work the identified parameters produce.
//
// Each trial value re-renders the rows' scenarios (the parameter changes what is computed), so the
// search is a bracketing one that needs few trials: false position with the Illinois correction, on
// the logarithm of the ratio. An integer parameter counts work (samples), so its bracket grows from
// the lower bound by doubling steps before false position narrows it to whole numbers.

#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "sim/core/param.h"

#include <functional>
#include <string>
#include <vector>

namespace pp5 {

struct IdentifiedWorkload {
    WorkloadSpec spec;
    double value = 0.0;        // identified
    ParamValue machine_value;  // what the recording machine's file gives, for comparison
    double reported_ratio = 0.0;
    double simulated_ratio = 0.0;  // at `value`
    int trials = 0;
    bool at_bound = false;  // the ratio cannot be reached inside the bounds: the nearest bound is kept
    std::string note;
};

struct WorkloadOptions {
    std::function<void(const std::string&)> progress;  // a line per trial, may be empty
};

// Identifies every [[workload]] parameter of `targets` in order. Targets without any give an empty list.
std::vector<IdentifiedWorkload> identify_workload(const TargetSet& targets, const WorkloadOptions& options);
std::vector<WorkloadSetting> workload_settings(const std::vector<IdentifiedWorkload>& identified);

}  // namespace pp5
