#pragma once
// The kernel interface: what every algorithm that runs on (or beside) the simulated machine offers the
// frontends and the calibration. A kernel describes itself and its parameters, says which scenario
// features it can render, and runs a scenario frame by frame: for each frame it computes the real
// pictures and records the machine's work (sim/timing/recorded_work.h) without timing it; whoever runs
// it times the work (sim/timing/frame_engine.h, or one_processor.h) and hands the timing back for the
// kernel's own account of the frame in stats.json.
//
// Adding a kernel: a folder under kernels/ with a class deriving from Kernel, and one line in
// kernels/registry/registry.cpp.

#include "scene/render/image.h"
#include "scene/scenario/scenario.h"
#include "scene/volume/volume.h"
#include "sim/core/param.h"
#include "sim/machine/machine.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

#include <nlohmann/json_fwd.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pp5 {

// One frame as a kernel computed it. Kernels derive from it to keep what their account needs.
struct KernelFrame {
    virtual ~KernelFrame() = default;
    std::vector<Image> pass_images;  // the picture after each stage (refinement pass); the last is the frame
    FrameWork work;                  // what the frame asks of the machine (empty: nothing to time)
    // Whoever has a reference picture compares every pass image with it (not only the last) and writes
    // each pass's difference image, for kernels whose stages are alternatives worth comparing.
    bool compare_passes_with_reference = false;
};

// A scenario being rendered by one kernel on one machine, frame after frame (state carries over:
// what a frame leaves in the PPs, the caches, a depth buffer).
class KernelRun {
public:
    virtual ~KernelRun() = default;
    virtual std::unique_ptr<KernelFrame> record_frame(const FrameSpec& frame) = 0;
    // The kernel's record of a timed frame for stats.json: what the frame did and where its time went
    // (`pass_images` names the files the frame's pass_images were written to).
    virtual nlohmann::json frame_stats(const KernelFrame& frame, const FrameTiming& timing,
                                       const std::vector<std::string>& pass_images) const = 0;
    // A line for the terminal about that frame.
    virtual std::string describe(const nlohmann::json& frame_stats) const = 0;
    // What the run set up once (how data sits in the machine), for stats.json; null when nothing.
    virtual nlohmann::json run_stats() const;
};

// A figure a kernel's frame can be measured by (a calibration target's metric).
struct KernelMetric {
    std::string name;  // "crude_seconds"
    std::string unit;  // "s"
    std::string description;
};

// A figure a kernel computes from a description rather than from a rendered frame: the size of a
// representation for a paper's data set that is not available here, say. A calibration target can
// name one (with the inputs) and compare it with the paper's figure.
struct FormulaInput {
    std::string name;   // "low_resolution"
    std::size_t count;  // how many numbers it is: 3 for sizes [x, y, z], 1 for a count
};
struct KernelFormula {
    std::string name;  // "storage_megabytes"
    std::string unit;
    std::string description;
    std::vector<FormulaInput> inputs;  // a target row gives each as a number or a list of `count` numbers
};
using FormulaInputs = std::map<std::string, std::vector<double>>;

// What a scenario may ask of a kernel beyond a volume, its classification and its lights. A scenario
// asking for what its kernel lacks is refused by the registry (check_scenario), which names the
// kernels that have it.
struct KernelFeatures {
    bool polygons = false;  // scan-converts the scenario's polygons with the volume
    bool regions = false;   // the volume-of-interest tool (a frame's region)
};

class Kernel {
public:
    virtual ~Kernel() = default;
    virtual std::string name() const = 0;
    virtual std::string description() const = 0;
    // How its simulated time comes about, for stats.json's summary (which adds the calibration in force).
    virtual std::string timing_summary() const = 0;
    // The kernel's own parameters ("<kernel>.*") and the machine's costs of its operations
    // ("gp_cost.<kernel>.*"), set like machine parameters.
    virtual std::vector<const ParamGroup*> param_groups() const = 0;
    // False for a kernel that only renders on the host: its frames record no work.
    virtual bool runs_on_machine() const = 0;
    // The most pictures a frame's pass_images holds on `config`, and whether each is compared with the
    // reference (a difference image each): what a run's up-front memory estimate counts.
    virtual std::size_t most_pictures_per_frame(const MachineConfig& /*config*/) const { return 1; }
    virtual bool compares_each_picture() const { return false; }
    virtual KernelFeatures features() const { return {}; }
    // Throws InputError naming the scenario's file and field for what else the kernel cannot render
    // (its resampling order, its lights); check_scenario (kernels/registry) checks the features too.
    virtual void check(const Scenario& scenario) const = 0;
    // What its frames can be measured by, and one frame's value of a metric once timed. Throws
    // std::domain_error saying why when the frame cannot give it (a polygon rate of a frame without
    // polygons).
    virtual std::vector<KernelMetric> metrics() const { return {}; }
    virtual double metric(const std::string& name, const KernelFrame& frame, const FrameTiming& timing) const;
    // Its formulas, and one's value (std::domain_error saying why when the inputs make no sense).
    virtual std::vector<KernelFormula> formulas() const { return {}; }
    virtual double formula(const std::string& name, const FormulaInputs& inputs) const;
    // InputError naming the machine key when a volume of `dims` could not be set up on `machine`: asked
    // before the volume is read when the scenario gives its size (a resampled dataset), so a volume
    // that cannot fit is refused without loading it. start() checks the same again.
    virtual void check_volume_fits(const Machine& /*machine*/, const MachineConfig& /*config*/,
                                   const Scenario& /*scenario*/, glm::ivec3 /*dims*/) const {}
    // Sets the scenario up on the machine (InputError when the data cannot fit, naming the key).
    virtual std::unique_ptr<KernelRun> start(Machine& machine, const MachineConfig& config, const Scenario& scenario,
                                             const Volume& volume) const = 0;
};

// For a kernel's check(): InputError naming the scenario's shading.stationary_lights when a frame has
// stationary lights that the kernel's cost model cannot count (`why` says what it counts instead).
void refuse_stationary_lights(const Scenario& scenario, const std::string& kernel, const std::string& why);

}  // namespace pp5
