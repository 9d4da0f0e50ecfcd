#include "dummy_kernel.h"

#include "sim/core/input_error.h"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace pp5::test {

namespace {

const ParamGroup& dummy_params() {
    static const ParamGroup group = [] {
        ParamGroup g("dummy", "The test tree's dummy kernel");
        g.integer("stripes", 4, "count", 1, 64, "Horizontal stripes in the picture", Provenance::Default, "test");
        return g;
    }();
    return group;
}

const ParamGroup& dummy_costs() {
    static const ParamGroup group = [] {
        ParamGroup g("gp_cost.dummy", "What the dummy kernel's GP operation costs");
        g.real("shade_flops", 10, "flops", 0, 1e6, "Shade one pixel", Provenance::Default, "test");
        return g;
    }();
    return group;
}

constexpr std::uint32_t kBlocks = 8;

struct DummyFrame final : KernelFrame {
    std::uint64_t pixels = 0;
};

class DummyRun final : public KernelRun {
public:
    DummyRun(const MachineConfig& config, const Scenario& scenario, std::size_t renderers)
        : stripes_(static_cast<int>(config.integer("dummy.stripes"))),
          width_(scenario.image.width),
          height_(scenario.image.height) {
        // Block b lives on renderer b mod R, 16 units of 32 bits.
        std::vector<std::uint32_t> first;
        std::vector<BlockPart> parts;
        for (std::uint32_t b = 0; b <= kBlocks; ++b) first.push_back(b);
        for (std::uint32_t b = 0; b < kBlocks; ++b)
            parts.push_back(BlockPart{static_cast<std::uint32_t>(b % renderers), 16});
        blocks_ = std::make_shared<const BlockDirectory>(16 * 32, 32, first, parts);
    }

    std::unique_ptr<KernelFrame> record_frame(const FrameSpec&) override {
        auto out = std::make_unique<DummyFrame>();
        Image coarse(width_, height_), striped(width_, height_);
        for (int y = 0; y < height_; ++y)
            for (int x = 0; x < width_; ++x) {
                coarse.at(x, y) = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
                const float band = static_cast<float>((y * stripes_ / height_) % 2);
                striped.at(x, y) = glm::vec4(band, band, band, 1.0f);
            }
        out->pass_images = {coarse, striped};

        FrameWork& work = out->work;
        work.op_kinds = {{"dummy.shade", {"gp_cost.dummy.shade_flops"}}};
        work.image_width = width_;
        work.image_height = height_;
        work.phases.push_back(Phase{"share", BroadcastPhase{std::vector<std::uint32_t>(16, 1), 128, {GpOp{0, 100}}}});
        GpPhase shade;
        shade.blocks = blocks_;
        shade.groups = 2;
        shade.ops.push_back(GpOp{0, 1});  // every step shades one pixel
        for (std::uint32_t pass = 0; pass < 2; ++pass)
            for (int y = 0; y < height_; ++y) {
                GpTask task{pass,
                            static_cast<std::uint32_t>(y),
                            static_cast<std::uint32_t>(shade.items.size()),
                            static_cast<std::uint32_t>(width_),
                            0,
                            0,
                            0,
                            0,
                            static_cast<std::uint32_t>(width_),
                            0,
                            0,
                            {}};
                for (int x = 0; x < width_; ++x) {
                    shade.items.push_back(GpItem{static_cast<std::uint32_t>(shade.steps.size()), 1});
                    shade.steps.push_back(GpStep{0, 1, static_cast<std::uint32_t>((x + y) % kBlocks)});
                }
                shade.tasks.push_back(task);
            }
        work.phases.push_back(Phase{"shade", std::move(shade)});
        out->pixels = 2ull * static_cast<std::uint64_t>(width_) * static_cast<std::uint64_t>(height_);
        return out;
    }

    nlohmann::json frame_stats(const KernelFrame& frame, const FrameTiming& timing,
                               const std::vector<std::string>& images) const override {
        return {{"dummy",
                 {{"pixels_shaded", static_cast<const DummyFrame&>(frame).pixels},
                  {"shade_seconds", ticks_to_seconds(timing.phase("shade")->duration_ps())},
                  {"pass_images", images}}}};
    }
    std::string describe(const nlohmann::json& f) const override {
        return "; dummy shaded " + f["dummy"]["pixels_shaded"].dump() + " pixels";
    }

private:
    int stripes_;
    int width_;
    int height_;
    std::shared_ptr<const BlockDirectory> blocks_;
};

class DummyKernel final : public Kernel {
public:
    std::string name() const override { return "dummy"; }
    std::string description() const override { return "stripes, for the registry's tests"; }
    std::string timing_summary() const override { return "event-driven: a broadcast, then a task per row"; }
    std::vector<const ParamGroup*> param_groups() const override { return {&dummy_params(), &dummy_costs()}; }
    bool runs_on_machine() const override { return true; }
    // No features (no polygons, no volume of interest): the registry refuses scenarios asking for them.
    void check(const Scenario&) const override {}
    std::unique_ptr<KernelRun> start(Machine& machine, const MachineConfig& config, const Scenario& scenario,
                                     const Volume&) const override {
        return std::make_unique<DummyRun>(config, scenario, machine.renderers().size());
    }
    std::vector<KernelMetric> metrics() const override { return {{"shade_seconds", "s", "the shading phase"}}; }
    double metric(const std::string& name, const KernelFrame& frame, const FrameTiming& timing) const override {
        if (name == "shade_seconds") return ticks_to_seconds(timing.phase("shade")->duration_ps());
        return Kernel::metric(name, frame, timing);
    }
};

}  // namespace

const Kernel& dummy_kernel() {
    static const DummyKernel kernel;
    return kernel;
}

}  // namespace pp5::test
