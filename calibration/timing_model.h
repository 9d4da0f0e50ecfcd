#pragma once
// The calibration's model: each target scenario is rendered once (the functional layer: images and the
// work every frame asks of the machine), and then timed again, as often as the fit needs, on machines
// that differ only in timing parameters (costs, clocks, counts of GPs, the calibration's scales). A
// Pixel-planes 5 machine times the work event by event (levoy_renderer.h); a uniprocessor (the Sun
// 4/280) times it as one processor's sum (sim/timing/one_processor.h). Re-timing gives exactly what a fresh
// render on that machine would (tests/unit/calibration), in a fraction of the time.

#include "calibration/targets.h"
#include "kernels/scenario/scenario.h"
#include "kernels/levoy/levoy_renderer.h"
#include "sim/core/calibration.h"
#include "sim/core/config.h"

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

// One frame's times on one machine, from which every metric is read.
struct FrameTimes {
    double crude_seconds = 0.0;
    double refined_seconds = 0.0;
    double pp_seconds = 0.0;  // classification and shading
    bool scan_converted = false;
    double polygons = 0.0;
    double scan_conversion_seconds = 0.0;
};
// The metric's value; throws InputError(targets file, field) when the frame cannot give it (no
// polygons for a polygon rate, no PP pass for pp_seconds).
double metric_value(Metric metric, const FrameTimes& times, const std::string& file, const std::string& field);

struct RecordedFrame {
    std::string label;
    LevoyFrameWork work;
    Image crude_image;    // after the first refinement pass
    Image refined_image;  // fully refined
};

// A scenario's frames rendered once on `functional` (a Pixel-planes 5 configuration), kept as work.
class RecordedScenario {
public:
    RecordedScenario(const Scenario& scenario, const MachineConfig& functional, int frames);

    // Every recorded frame's times on `machine`, frames in order (caches carry over between frames on
    // a multicomputer). Throws InputError naming the machine file's key if `machine` differs from the
    // recording machine in anything but timing.
    std::vector<FrameTimes> time_on(const MachineConfig& machine) const;

    const Scenario& scenario() const { return scenario_; }
    const std::vector<RecordedFrame>& frames() const { return frames_; }

private:
    Scenario scenario_;
    MachineConfig functional_;
    std::vector<RecordedFrame> frames_;
};

// Whether `key` only changes when things happen, never what is computed.
bool is_timing_parameter(const std::string& key);

// The targets' scenarios recorded once, and their machines' configurations; simulates any target on
// its machine with given calibration scales.
class CalibrationModel {
public:
    // Records every scenario the targets name, on the functional configuration `functional` (unless
    // given, the first Pixel-planes 5 machine the targets name).
    explicit CalibrationModel(const TargetSet& targets, std::optional<MachineConfig> functional = std::nullopt);

    // The targets' simulated values, on their machine with `scales` applied.
    std::vector<double> simulate(const std::string& machine, const CalibrationScales& scales,
                                 const std::vector<const Target*>& targets) const;
    // The machine's configuration (its preset or file) with `scales` applied.
    MachineConfig machine_config(const std::string& machine, const CalibrationScales& scales) const;
    const MachineConfig& base_config(const std::string& machine) const;
    const RecordedScenario& recording(const std::string& scenario) const;
    const TargetSet& targets() const { return targets_; }

private:
    TargetSet targets_;
    std::map<std::string, MachineConfig> machines_;
    std::map<std::string, std::unique_ptr<RecordedScenario>> scenarios_;
};

}  // namespace pp5
