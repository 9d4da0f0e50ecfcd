#include "kernels/levoy/levoy_kernel.h"

#include "kernels/levoy/levoy_costs.h"
#include "kernels/shared/pp_volume/pp_shading.h"
#include "kernels/shared/pp_volume/voxel_store_costs.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <stdexcept>

namespace pp5 {

LevoyImageSettings levoy_image_settings(const ImageSpec& spec) {
    LevoyImageSettings image;
    image.width = spec.width;
    image.height = spec.height;
    image.sample_step = spec.sample_step;
    image.termination_opacity = spec.termination_opacity;
    image.background = spec.background;
    return image;
}

LevoyFrameInputs levoy_frame_inputs(const FrameSpec& frame, const Volume& volume) {
    return LevoyFrameInputs{frame_camera(frame, volume),  frame.classification,   frame.colors, frame.lighting,
                            frame.classification_changed, frame.lighting_changed, frame.region};
}

namespace {

double seconds(Tick t) { return ticks_to_seconds(t); }

nlohmann::json pass_record(const PpProgramPass& pass) {
    if (!pass.ran) return {{"ran", false}};
    return {
        {"ran", true},
        {"simulated_seconds", static_cast<double>(pass.end_ps - pass.start_ps) / static_cast<double>(kTicksPerSecond)},
        {"instructions", pass.instructions},
        {"local_memory_bits_used", pass.local_memory_bits_used},
        {"slot_cycles", pass.slot_cost.compute_cycles()},
        {"slot_alu_cycles", pass.slot_cost.alu_cycles},
        {"slot_controller_cycles", pass.slot_cost.controller_cycles},
        {"slot_transfer_cycles", pass.slot_cost.transfer_cycles()},
        {"slots", pass.slots},
        {"cycles",
         {{"total", pass.busiest.total},
          {"computation", pass.busiest.alu},
          {"controller", pass.busiest.controller},
          {"backing_store", pass.busiest.backing_store_stall}}}};
}

// The machine's side of a frame: where the time went and what the GPs did.
nlohmann::json machine_record(const LevoyFrameReport& f, const std::vector<std::string>& pass_images) {
    const RayCastReport& rc = f.ray_cast;
    const double cast_seconds = seconds(rc.end - rc.start);
    const double gps = rc.gp_busy + rc.gp_wait > 0 ? 1.0 : 0.0;
    nlohmann::json passes = nlohmann::json::array();
    for (std::size_t i = 0; i < f.passes.size(); ++i) {
        const RefinementPassReport& p = f.passes[i];
        passes.push_back({{"pass", i},
                          {"image", pass_images.at(i)},
                          {"complete_seconds", seconds(p.end_ps)},
                          {"rays", p.rays},
                          {"samples", p.samples},
                          {"pixels_cast_so_far", p.pixels_cast}});
    }
    const std::uint64_t lookups = rc.cache_hits + rc.cache_misses;
    return {{"simulated_seconds", seconds(f.duration_ps())},
            {"crude_seconds", f.passes.empty() ? 0.0 : seconds(f.passes.front().end_ps)},
            {"refined_seconds", seconds(f.duration_ps())},
            {"phases",
             {{"pixel_processors_seconds", seconds(f.pixel_processors.duration_ps())},
              {"pyramid_seconds", seconds(f.pyramid_ps)},
              {"ray_casting_seconds", cast_seconds}}},
            {"ray_casting_breakdown",
             {{"gp_computing_seconds", seconds(rc.gp_busy)},
              {"gp_waiting_seconds", seconds(rc.gp_wait)},
              {"ring_busy_seconds", seconds(rc.ring_busy)},
              {"renderers_answering_seconds", seconds(rc.renderer_busy)},
              {"note", "each summed over the GPs, channels or renderers; ray_casting_seconds is wall time"},
              {"gp_busy_fraction",
               gps > 0 ? static_cast<double>(rc.gp_busy) / static_cast<double>(rc.gp_busy + rc.gp_wait) : 0.0}}},
            {"pyramid_rebuilt", f.pyramid_rebuilt},
            {"pyramid_cells_occupied", f.pyramid_cells_occupied},
            {"caches_invalidated", f.caches_invalidated},
            {"caches_refreshed", f.caches_refreshed},
            {"depth_buffer_used", f.depth_buffer_used},
            {"rays", rc.rays},
            {"samples", rc.samples},
            {"samples_skipped", rc.samples_skipped},
            {"pyramid_steps", rc.pyramid_steps},
            {"rays_terminated", rc.rays_terminated},
            {"pixels_filled", rc.pixels_filled},
            {"fetch_requests", rc.fetch_requests},
            {"cache_hits", rc.cache_hits},
            {"cache_misses", rc.cache_misses},
            {"cache_hit_rate", lookups == 0 ? 0.0 : static_cast<double>(rc.cache_hits) / static_cast<double>(lookups)},
            {"blocks_refreshed", rc.blocks_refreshed},
            {"context_switches", rc.context_switches},
            {"events", rc.events},
            {"passes", passes}};
}

struct LevoyKernelFrame final : KernelFrame {
    LevoyFrameReport report;
};

class LevoyRun final : public KernelRun {
public:
    LevoyRun(Machine& machine, const MachineConfig& config, const Scenario& scenario, const Volume& volume)
        : volume_(volume),
          renderer_(machine, volume, LevoySettings::for_scenario(config, scenario),
                    levoy_image_settings(scenario.image)) {
        renderer_.set_polygons(scenario.polygons);
    }

    std::unique_ptr<KernelFrame> record_frame(const FrameSpec& frame) override {
        auto out = std::make_unique<LevoyKernelFrame>();
        out->report = renderer_.record(levoy_frame_inputs(frame, volume_));
        for (RefinementPassReport& pass : out->report.passes) out->pass_images.push_back(std::move(pass.image));
        out->report.final_image = Image();  // the last pass image is the frame
        out->work = std::move(out->report.work.machine);
        return out;
    }

    nlohmann::json frame_stats(const KernelFrame& kernel_frame, const FrameTiming& timing,
                               const std::vector<std::string>& pass_images) const override {
        const auto& frame = static_cast<const LevoyKernelFrame&>(kernel_frame);
        LevoyFrameReport f = frame.report;
        apply_timing(f, levoy_frame_timing(f.work, timing));
        const GeometryReport& g = f.geometry;
        return {{"renderers",
                 {{"classification", pass_record(f.pixel_processors.classification)},
                  {"region_of_interest", pass_record(f.region)},
                  {"stationary_lights", pass_record(f.pixel_processors.stationary_lights)},
                  {"shading", pass_record(f.pixel_processors.shading)}}},
                {"geometry",
                 {{"ran", g.ran},
                  {"polygons", g.polygons},
                  {"slot_runs", g.slots},
                  {"simulated_seconds", seconds(g.end_ps - g.start_ps)},
                  {"polygons_per_second", g.polygons_per_second()}}},
                {"machine", machine_record(f, pass_images)}};
    }

    std::string describe(const nlohmann::json& f) const override {
        std::string line;
        for (const char* pass : {"classification", "region_of_interest", "stationary_lights", "shading"}) {
            const auto& p = f["renderers"][pass];
            if (!p["ran"].get<bool>()) continue;
            line += fmt::format("; PP {} {:.2f} ms ({} cycles a slot)", pass,
                                p["simulated_seconds"].get<double>() * 1e3, p["slot_cycles"].dump());
        }
        if (f["geometry"]["ran"].get<bool>())
            line +=
                fmt::format("; {} polygons scan-converted in {:.2f} ms ({:.0f} a second)",
                            f["geometry"]["polygons"].dump(), f["geometry"]["simulated_seconds"].get<double>() * 1e3,
                            f["geometry"]["polygons_per_second"].get<double>());
        const auto& m = f["machine"];
        const double crude = m["crude_seconds"].get<double>();
        line += fmt::format(
            "\n    GPs: {} rays in {} passes, {} samples ({} skipped), cache hit rate {:.1f}%; crude {:.1f} ms{}, "
            "refined {:.1f} ms simulated",
            m["rays"].dump(), m["passes"].size(), m["samples"].dump(), m["samples_skipped"].dump(),
            100.0 * m["cache_hit_rate"].get<double>(), crude * 1e3,
            crude > 0 ? fmt::format(" ({:.1f} a second)", 1.0 / crude) : std::string(),
            m["refined_seconds"].get<double>() * 1e3);
        // Where the frame's time went, phase by phase (each phase starts when the one before ends).
        const auto& phases = m["phases"];
        const auto ms = [&](const char* key) { return phases[key].get<double>() * 1e3; };
        line +=
            fmt::format("\n    time: PPs {:.2f} ms, pyramid {:.2f} ms, ray casting {:.2f} ms with the GPs {:.0f}% busy",
                        ms("pixel_processors_seconds"), ms("pyramid_seconds"), ms("ray_casting_seconds"),
                        100.0 * m["ray_casting_breakdown"].value("gp_busy_fraction", 0.0));
        return line;
    }

    nlohmann::json run_stats() const override {
        const VoxelPlacement& p = renderer_.pixel_processors().placement();
        const VoxelQuantization& q = renderer_.pixel_processors().quantization();
        return {{"policy", to_string(p.policy())},
                {"record_bits", p.record_bits()},
                {"slots_needed", p.slots_needed()},
                {"slots_available", p.slots_available()},
                {"backing_store_bits_used", p.backing_store_bits_used()},
                {"value_scale", q.value_scale},
                {"value_offset", q.value_offset},
                {"gradient_scale", q.gradient_scale}};
    }

private:
    const Volume& volume_;
    LevoyRenderer renderer_;
};

class LevoyKernel final : public Kernel {
public:
    std::string name() const override { return "levoy"; }
    std::string description() const override {
        return "Levoy 1989: the renderers' PPs classify and shade the volume, the GPs cast rays with the pyramid of "
               "binary "
               "volumes, early termination and adaptive refinement, fetching voxels over the ring into their caches";
    }
    std::string timing_summary() const override {
        return "event-driven: PP passes from their programs' operations, the pyramid's distribution and building, and "
               "the GPs' "
               "ray casting with voxel requests over the ring";
    }
    std::vector<const ParamGroup*> param_groups() const override {
        return {&VoxelStoreSettings::placement_params(), &VoxelStoreSettings::layout_params(), &LevoySettings::params(),
                &levoy_cost_params(), &voxel_store_cost_params()};
    }
    bool runs_on_machine() const override { return true; }
    // A pass for each halving of the first pass's spacing, down to one pixel.
    std::size_t most_pictures_per_frame(const MachineConfig& config) const override {
        std::size_t passes = 1;
        for (std::int64_t spacing = config.integer("levoy.refinement_spacing"); spacing > 1;
             spacing = (spacing + 1) / 2)
            ++passes;
        return passes;
    }
    KernelFeatures features() const override { return {.polygons = true, .regions = true}; }
    void check(const Scenario& scenario) const override {
        if (scenario.image.resampling != ResamplingOrder::ShadeThenInterpolate)
            throw InputError(
                scenario.file.string(), "image.resampling",
                "the levoy kernel shades at the voxels (shade-then-interpolate); use kernel = \"reference\" to "
                "interpolate first");
    }
    void check_volume_fits(const Machine& machine, const MachineConfig& config, const Scenario& scenario,
                           glm::ivec3 dims) const override {
        LevoyRenderer::check_fits(machine, dims, LevoySettings::for_scenario(config, scenario));
    }
    std::unique_ptr<KernelRun> start(Machine& machine, const MachineConfig& config, const Scenario& scenario,
                                     const Volume& volume) const override {
        return std::make_unique<LevoyRun>(machine, config, scenario, volume);
    }

    std::vector<KernelMetric> metrics() const override {
        return {{"crude_seconds", "s", "the frame's first refinement pass on screen"},
                {"refined_seconds", "s", "the frame fully refined"},
                {"refinement_seconds", "s", "refined minus crude: \"a further 57 s\""},
                {"pp_seconds", "s", "classification and shading of the volume by the PPs"},
                {"polygons_per_second", "1/s", "3D scan-conversion rate"},
                {"seconds_per_polygon", "s", "3D scan-conversion time per polygon"},
                {"speedup_for_30_fps", "factor", "how much faster the crude frame must get for 30 frames a second"}};
    }

    double metric(const std::string& name, const KernelFrame& kernel_frame, const FrameTiming& timing) const override {
        const auto& frame = static_cast<const LevoyKernelFrame&>(kernel_frame);
        const LevoyFrameTiming t = levoy_frame_timing(frame.report.work, timing);
        const double crude = ticks_to_seconds(t.crude_ps());
        const double refined = ticks_to_seconds(t.refined_ps());
        const double scan = ticks_to_seconds(t.geometry.end_ps - t.geometry.start_ps);
        const auto polygons = static_cast<double>(t.geometry.polygons);
        const auto need_polygons = [&] {
            if (!t.geometry.ran || polygons == 0.0 || scan <= 0.0)
                throw std::domain_error("the frame scan-converts no polygons, so it has no polygon rate");
        };
        if (name == "crude_seconds") return crude;
        if (name == "refined_seconds") return refined;
        if (name == "refinement_seconds") return refined - crude;
        if (name == "pp_seconds") {
            const double pp = ticks_to_seconds(t.pixel_processors.duration_ps());
            if (pp <= 0.0) throw std::domain_error("the frame runs no classification or shading pass");
            return pp;
        }
        if (name == "polygons_per_second" || name == "seconds_per_polygon") {
            need_polygons();
            return name == "polygons_per_second" ? polygons / scan : scan / polygons;
        }
        if (name == "speedup_for_30_fps") return crude * 30.0;
        return Kernel::metric(name, kernel_frame, timing);
    }
};

}  // namespace

const Kernel& levoy_kernel() {
    static const LevoyKernel kernel;
    return kernel;
}

}  // namespace pp5
