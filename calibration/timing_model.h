#pragma once
// The calibration's model: each target scenario is rendered once (the functional layer: images and the
// work every frame asks of the machine), and then timed again, as often as the fit needs, on machines
// that differ only in timing parameters (costs, clocks, counts of GPs, the calibration's scales). A
// Pixel-planes 5 machine times the work event by event (sim/timing/frame_engine.h); a uniprocessor (the Sun
// 4/280) times it as one processor's sum (sim/timing/one_processor.h). Re-timing gives exactly what a fresh
// render on that machine would (tests/unit/calibration), in a fraction of the time.

#include "calibration/targets.h"
#include "kernels/api/kernel.h"
#include "scene/scenario/scenario.h"
#include "sim/core/calibration.h"
#include "sim/core/config.h"

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

// Recorded frames' work timed in order on `machine`: a Pixel-planes 5 machine event by event (its
// caches carry over from frame to frame), a uniprocessor as one processor's sum.
std::vector<FrameTiming> time_recorded_work(const MachineConfig& machine, const std::vector<const FrameWork*>& work);

struct RecordedFrame {
    std::string label;
    std::unique_ptr<KernelFrame> frame;  // the kernel's record, with the machine's work
    Image crude_image;                   // after the first stage (refinement pass)
    Image refined_image;                 // the finished frame
};

// A scenario's frames rendered once by its kernel on `functional` (a Pixel-planes 5 configuration),
// kept as work.
class RecordedScenario {
public:
    RecordedScenario(const Scenario& scenario, const MachineConfig& functional, int frames);

    // Every recorded frame's times on `machine`, frames in order (caches carry over between frames on
    // a multicomputer). Throws InputError naming the machine file's key if `machine` differs from the
    // recording machine in anything but timing.
    std::vector<FrameTiming> time_on(const MachineConfig& machine) const { return time_on(machine, frames_.size()); }
    // Only the first `frames` (later frames cannot change earlier ones' times).
    std::vector<FrameTiming> time_on(const MachineConfig& machine, std::size_t frames) const;
    // A recorded frame's value of one of its kernel's metrics, timed as `timing`; throws
    // std::domain_error when the frame cannot give it.
    double metric(const std::string& name, std::size_t frame, const FrameTiming& timing) const;

    const Scenario& scenario() const { return scenario_; }
    const Kernel& kernel() const { return kernel_; }
    const std::vector<RecordedFrame>& frames() const { return frames_; }

private:
    Scenario scenario_;
    const Kernel& kernel_;
    MachineConfig functional_;
    std::vector<RecordedFrame> frames_;
};

// The machine the targets' work is recorded on: the first Pixel-planes 5 machine the rows name (every
// machine must compute the same; RecordedScenario::time_on checks), or the first machine when all are
// uniprocessors.
MachineConfig recording_machine(const TargetSet& targets);

// Whether `key` only changes when things happen, never what is computed: as its parameter declares it
// (ParamSpec::timing_only); false for a key no machine or kernel declares.
bool is_timing_parameter(const std::string& key);
// Recorded work can be re-timed on `timing` only if it computes what `recorded` did: an InputError
// names the first parameter that differs and is not a timing one (and where `timing` got it), ending
// with `remedy`.
void check_only_timing_differs(const MachineConfig& recorded, const MachineConfig& timing, const std::string& remedy);

// A functional parameter's value (one the workload step identified), set on every machine a model
// records or times with.
struct WorkloadSetting {
    std::string key;
    double value = 0.0;
    bool integer = false;
    ParamValue param_value() const {
        return integer ? ParamValue(static_cast<std::int64_t>(std::llround(value))) : ParamValue(value);
    }
};

// The targets' scenarios recorded once, and their machines' configurations; simulates any target on
// its machine with given calibration scales.
class CalibrationModel {
public:
    // Records every scenario the targets name, on the functional configuration `functional` (unless
    // given, the first Pixel-planes 5 machine the targets name), with `workload` set on it and on
    // every target's machine.
    // `progress` hears of each scenario as its recording starts.
    explicit CalibrationModel(const TargetSet& targets, std::optional<MachineConfig> functional = std::nullopt,
                              std::vector<WorkloadSetting> workload = {},
                              const std::function<void(const std::string&)>& progress = {});

    // The targets' simulated values, on their machine with `scales` applied.
    std::vector<double> simulate(const std::string& machine, const CalibrationScales& scales,
                                 const std::vector<const Target*>& targets) const;
    // The same on a configuration of one of the targets' machines, changed in timing only.
    std::vector<double> simulate_on(const MachineConfig& config, const std::vector<const Target*>& targets) const;
    // A formula row's value (Target::is_formula), from its kernel.
    double formula_value(const Target& target) const;
    // The machine's configuration (its preset or file) with `scales` applied.
    MachineConfig machine_config(const std::string& machine, const CalibrationScales& scales) const;
    const MachineConfig& base_config(const std::string& machine) const;
    const RecordedScenario& recording(const std::string& scenario) const;
    const TargetSet& targets() const { return targets_; }
    const std::vector<WorkloadSetting>& workload() const { return workload_; }

private:
    TargetSet targets_;
    std::vector<WorkloadSetting> workload_;
    std::map<std::string, MachineConfig> machines_;
    std::map<std::string, std::unique_ptr<RecordedScenario>> scenarios_;
};

}  // namespace pp5
