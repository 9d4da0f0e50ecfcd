#include "kernels/reference_kernel/reference_kernel.h"

#include "scene/reference/reference_renderer.h"
#include "scene/scenario/scenario_inputs.h"

#include <nlohmann/json.hpp>

namespace pp5 {

namespace {

struct ReferenceFrame final : KernelFrame {
    RenderStats stats;
};

class ReferenceRun final : public KernelRun {
public:
    ReferenceRun(const Scenario& scenario, const Volume& volume)
        : volume_(volume), renderer_(volume), settings_(reference_render_settings(scenario.image)) {
        renderer_.set_polygons(scenario.polygons);
    }

    std::unique_ptr<KernelFrame> record_frame(const FrameSpec& frame) override {
        if (frame.classification_changed) renderer_.set_classification(frame.classification, frame.colors);
        if (frame.lighting_changed) renderer_.set_lighting(frame.lighting);
        renderer_.set_region(frame.region);
        auto out = std::make_unique<ReferenceFrame>();
        out->pass_images.push_back(renderer_.render(frame_camera(frame, volume_), settings_, &out->stats));
        return out;
    }
    nlohmann::json frame_stats(const KernelFrame& frame, const FrameTiming&,
                               const std::vector<std::string>&) const override {
        return {{"reference", reference_stats(static_cast<const ReferenceFrame&>(frame).stats)}};
    }
    std::string describe(const nlohmann::json&) const override { return {}; }

private:
    const Volume& volume_;
    ReferenceRenderer renderer_;
    RenderSettings settings_;
};

class ReferenceKernel final : public Kernel {
public:
    std::string name() const override { return "reference"; }
    std::string description() const override { return "the host floating-point renderer alone (no simulated time)"; }
    std::string timing_summary() const override { return "none: the host reference renderer; simulated time is 0"; }
    // Its frames take no simulated time; what its loop costs a processor (gp_cost.reference.*) prices
    // `pp5sim host-check`'s runs, and is declared with the run configuration (run_config.cpp).
    std::vector<const ParamGroup*> param_groups() const override { return {}; }
    bool runs_on_machine() const override { return false; }
    KernelFeatures features() const override { return {.polygons = true, .regions = true}; }
    void check(const Scenario&) const override {}
    std::unique_ptr<KernelRun> start(Machine&, const MachineConfig&, const Scenario& scenario,
                                     const Volume& volume) const override {
        return std::make_unique<ReferenceRun>(scenario, volume);
    }
};

}  // namespace

const Kernel& reference_kernel() {
    static const ReferenceKernel kernel;
    return kernel;
}

}  // namespace pp5
