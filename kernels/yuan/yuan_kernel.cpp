#include "kernels/yuan/yuan_kernel.h"

#include "kernels/shared/pp_volume/pp_shading.h"
#include "kernels/shared/pp_volume/voxel_store_costs.h"
#include "kernels/shared/screen_regions/region_machine.h"
#include "kernels/shared/screen_regions/screen_region_costs.h"
#include "kernels/yuan/hybrid_splatter.h"
#include "kernels/yuan/yuan_costs.h"
#include "scene/reference/shading_view.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace pp5 {

namespace {

double seconds(Tick t) { return ticks_to_seconds(t); }

struct YuanFrame final : KernelFrame {
    SplatCounts counts;
    bool classified = false;
    bool shaded = false;
};

class YuanRun final : public KernelRun {
public:
    YuanRun(Machine& machine, const MachineConfig& config, const Scenario& scenario, const Volume& volume)
        : volume_(volume),
          image_(scenario.image),
          voxel_store_(machine, volume, VoxelStoreSettings::from(config)),
          splatter_(YuanSettings::from(config), splat_machine(machine, voxel_store_), volume.dims(), volume.spacing()) {
    }

    std::unique_ptr<KernelFrame> record_frame(const FrameSpec& frame) override {
        auto out = std::make_unique<YuanFrame>();
        const Camera camera = frame_camera(frame, volume_);
        // The PPs reshade only when the colours depend on what changed (as Levoy's kernel decides).
        ShadingView view = make_shading_view(camera, volume_.dims(), volume_.spacing());
        if (shaded_for_ && !shading_depends_on_view(frame.lighting)) view = *shaded_for_;
        const bool classify = first_frame_ || frame.classification_changed;
        const bool reshade = classify || frame.lighting_changed || shaded_for_ != view;
        const PpFrameWork pp =
            voxel_store_.compute(frame.classification, frame.colors, frame.lighting, view, classify, reshade);
        FrameWork& work = out->work;
        work.op_kinds = yuan_op_kinds();
        const std::uint64_t voxels = static_cast<std::uint64_t>(volume_.samples().size());
        const auto voxel_pass = [&](const char* name, const PpPassWork& pass, YuanOp per_voxel,
                                    std::uint64_t per_voxel_count) {
            PpPhase phase{{PpPhase::Pass{pass, 0, {}}}};
            append_ops(phase.passes.front().on_one_processor, per_voxel, voxels * per_voxel_count);
            work.phases.push_back(Phase{name, std::move(phase)});
        };
        if (pp.classification) voxel_pass("classification", *pp.classification, kYuanVoxelClassification, 1);
        // A lone processor shades each voxel once per light (the voxel store keeps no stationary sum here).
        if (pp.shading)
            voxel_pass("shading", *pp.shading, kYuanVoxelShading, 1 + frame.lighting.stationary_lights.size());
        if (pp.classification || pp.shading) voxel_store_.read_shaded_codes(shaded_);
        shaded_for_ = view;
        first_frame_ = false;

        SplatFrame splats = splatter_.render(shaded_, camera, image_.width, image_.height, image_.background);
        work.phases.push_back(Phase{"splatting", std::move(splats.work)});
        // New colours in the PPs make the GPs' cached bricks stale.
        work.invalidate_gp_caches = pp.classification.has_value() || pp.shading.has_value();
        work.image_width = image_.width;
        work.image_height = image_.height;
        out->counts = std::move(splats.counts);
        out->classified = pp.classification.has_value();
        out->shaded = pp.shading.has_value();
        out->pass_images.push_back(std::move(splats.primitive_map));
        out->pass_images.push_back(std::move(splats.image));
        return out;
    }

    nlohmann::json frame_stats(const KernelFrame& kernel_frame, const FrameTiming& timing,
                               const std::vector<std::string>& pass_images) const override {
        const auto& frame = static_cast<const YuanFrame&>(kernel_frame);
        const SplatCounts& c = frame.counts;
        nlohmann::json phases = nlohmann::json::object();
        for (const PhaseTiming& p : timing.phases) phases[p.name + "_seconds"] = seconds(p.duration_ps());
        nlohmann::json out = {
            {"simulated_seconds", seconds(timing.duration_ps())},
            {"phases", phases},
            {"images", {{"primitives", pass_images.at(0)}, {"frame", pass_images.at(1)}}},
            {"classified", frame.classified},
            {"reshaded", frame.shaded},
            {"voxels", c.voxels},
            {"splats", c.splats},
            {"points", c.points},
            {"splat_fraction", c.splat_fraction()},
            {"culled", c.culled},
            {"offscreen", c.offscreen},
            {"bands", c.bands},
            {"chunks", c.chunks},
            {"batches", c.batches},
            {"batch_words", c.batch_words},
            {"splat_draws", c.splat_regions},
            {"point_draws", c.point_regions},
            {"regions_per_splat",
             c.splats == 0 ? 0.0 : static_cast<double>(c.splat_regions) / static_cast<double>(c.splats)},
            {"splat_pixels", c.splat_pixels},
            {"point_pixels", c.point_pixels},
            {"band_composites", c.band_composites},
            {"composited_pixels", c.composited_pixels},
            {"footprint_rows", c.footprint_rows},
            {"primitives_per_region", c.primitives_per_region}};
        if (const PhaseTiming* s = timing.phase("splatting")) out["splatting"] = region_phase_stats(s->gp);
        return out;
    }

    std::string describe(const nlohmann::json& f) const override {
        std::string line =
            fmt::format("; {} voxels: {} splats ({:.1f}%), {} points in {} bands; {:.1f} ms simulated",
                        f["voxels"].dump(), f["splats"].dump(), 100 * f["splat_fraction"].get<double>(),
                        f["points"].dump(), f["bands"].dump(), f["simulated_seconds"].get<double>() * 1e3);
        if (f.contains("splatting"))
            line += fmt::format(" (renderer imbalance {:.2f})", f["splatting"]["renderer_imbalance"].get<double>());
        return line;
    }

    nlohmann::json run_stats() const override {
        const VoxelPlacement& p = voxel_store_.placement();
        return {{"policy", to_string(p.policy())},
                {"record_bits", p.record_bits()},
                {"slots_needed", p.slots_needed()},
                {"backing_store_bits_used", p.backing_store_bits_used()}};
    }

private:
    static RegionMachine splat_machine(const Machine& machine, const PpShading& store) {
        const VoxelPlacement* placement = &store.placement();
        return RegionMachine::from(machine, [placement](glm::ivec3 v) { return placement->locate(v).renderer; });
    }

    const Volume& volume_;
    ImageSpec image_;
    PpShading voxel_store_;
    HybridSplatter splatter_;
    ShadedCodes shaded_;
    std::optional<ShadingView> shaded_for_;
    bool first_frame_ = true;
};

class YuanKernel final : public Kernel {
public:
    std::string name() const override { return "yuan"; }
    std::string description() const override {
        return "Yuan et al. 2003: hybrid forward resampling; the PPs shade the voxels, the GPs make minified voxels "
               "points and "
               "magnified ones perspective elliptical splats and bin them by screen region, the renderers draw them "
               "through "
               "the QEE and composite in fixed point";
    }
    std::string timing_summary() const override {
        return "event-driven: PP shading passes, then the GPs' bricks fetched over the ring and turned into primitive "
               "batches, "
               "drawn by each renderer in depth order from its region programs' operations";
    }
    std::vector<const ParamGroup*> param_groups() const override {
        return {&VoxelStoreSettings::placement_params(),
                &VoxelStoreSettings::layout_params(),
                &YuanSettings::params(),
                &yuan_cost_params(),
                &voxel_store_cost_params(),
                &screen_region_cost_params()};
    }
    bool runs_on_machine() const override { return true; }
    std::size_t most_pictures_per_frame(const MachineConfig&) const override {
        return 2;
    }  // the primitive map, the frame
    void check(const Scenario& scenario) const override {
        const std::string file = scenario.file.string();
        if (scenario.image.resampling != ResamplingOrder::ShadeThenInterpolate)
            throw InputError(file, "image.resampling", "the yuan kernel splats shaded voxels (shade-then-interpolate)");
    }
    void check_volume_fits(const Machine& machine, const MachineConfig& config, const Scenario& /*scenario*/,
                           glm::ivec3 dims) const override {
        PpShading::check_fits(machine, dims, VoxelStoreSettings::from(config));
    }
    std::unique_ptr<KernelRun> start(Machine& machine, const MachineConfig& config, const Scenario& scenario,
                                     const Volume& volume) const override {
        return std::make_unique<YuanRun>(machine, config, scenario, volume);
    }
    std::vector<KernelMetric> metrics() const override {
        return {{"frame_seconds", "s", "the whole frame: PP passes and splatting"},
                {"splatting_seconds", "s", "the GPs' and renderers' splatting alone"},
                {"splat_fraction", "fraction", "of the voxels drawn, the share drawn as splats (Figure 9's brackets)"}};
    }
    double metric(const std::string& name, const KernelFrame& kernel_frame, const FrameTiming& timing) const override {
        const auto& frame = static_cast<const YuanFrame&>(kernel_frame);
        if (name == "frame_seconds") return seconds(timing.duration_ps());
        if (name == "splatting_seconds") {
            const PhaseTiming* s = timing.phase("splatting");
            if (s == nullptr) throw std::domain_error("the frame has no splatting phase");
            return seconds(s->duration_ps());
        }
        if (name == "splat_fraction") {
            if (frame.counts.splats + frame.counts.points == 0) throw std::domain_error("the frame draws no voxels");
            return frame.counts.splat_fraction();
        }
        return Kernel::metric(name, kernel_frame, timing);
    }
};

}  // namespace

const Kernel& yuan_kernel() {
    static const YuanKernel kernel;
    return kernel;
}

}  // namespace pp5
