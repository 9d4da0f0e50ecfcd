#include "kernels/wilson/wilson_kernel.h"

#include "kernels/shared/pp_volume/pp_shading.h"
#include "kernels/shared/pp_volume/voxel_store_costs.h"
#include "kernels/shared/screen_regions/region_machine.h"
#include "kernels/shared/screen_regions/screen_region_costs.h"
#include "kernels/wilson/hybrid_slicer.h"
#include "kernels/wilson/hybrid_volume.h"
#include "kernels/wilson/wilson_costs.h"
#include "scene/reference/shading_view.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace pp5 {

namespace {

double seconds(Tick t) { return ticks_to_seconds(t); }

// The classification as it must read a volume whose voxels are k times larger: a gradient measured per
// low-resolution voxel is k times the original's, so the thickness of an isovalue contour (in voxels)
// and the opacity a region boundary gives per unit of gradient both shrink by k.
Classification for_voxels_of(const Classification& c, int k) {
    Classification out = c;
    if (out.kind == ClassificationKind::IsovalueContours)
        for (IsovalueContour& contour : out.contours) contour.thickness /= static_cast<float>(k);
    if (out.kind == ClassificationKind::RegionBoundaries)
        for (OpacityPoint& p : out.points) p.opacity /= static_cast<float>(k);
    return out;
}

bool uses_gradient(const Scenario& scenario) {
    return std::any_of(scenario.frames.begin(), scenario.frames.end(),
                       [](const FrameSpec& f) { return f.classification.kind != ClassificationKind::PiecewiseLinear; });
}

struct WilsonFrame final : KernelFrame {
    HybridCounts counts;
    std::array<std::uint64_t, 5> paper_thresholds{};  // the representation's error samples past each paper threshold
    bool classified = false;
    bool shaded = false;
};

class WilsonRun final : public KernelRun {
public:
    WilsonRun(Machine& machine, const MachineConfig& config, const Scenario& scenario, const Volume& volume)
        : volume_(volume),
          image_(scenario.image),
          settings_(WilsonSettings::from(config)),
          hybrid_(HybridVolume::build(volume, settings_, uses_gradient(scenario))),
          voxel_store_(machine, hybrid_.low_resolution(), VoxelStoreSettings::from(config)),
          slicer_(settings_, slice_machine(machine, voxel_store_), hybrid_, volume.spacing()),
          resident_bits_by_brick_(slicer_.resident_bits_by_brick()) {
        check_points_fit(machine);
    }

    std::unique_ptr<KernelFrame> record_frame(const FrameSpec& frame) override {
        auto out = std::make_unique<WilsonFrame>();
        const Camera camera = frame_camera(frame, volume_);
        const Volume& low = hybrid_.low_resolution();
        // The PPs reshade the low-resolution voxels only when their colours depend on what changed.
        ShadingView view = make_shading_view(camera, low.dims(), low.spacing());
        if (shaded_for_ && !shading_depends_on_view(frame.lighting)) view = *shaded_for_;
        const bool classify = first_frame_ || frame.classification_changed;
        const bool reshade = classify || frame.lighting_changed || shaded_for_ != view;
        if (classify) classification_ = for_voxels_of(frame.classification, hybrid_.factor());
        const PpFrameWork pp =
            voxel_store_.compute(classification_, frame.colors, frame.lighting, view, classify, reshade);
        FrameWork& work = out->work;
        work.op_kinds = wilson_op_kinds();
        const std::uint64_t voxels = static_cast<std::uint64_t>(low.samples().size());
        const auto voxel_pass = [&](const char* name, const PpPassWork& pass, WilsonOp per_voxel) {
            PpPhase phase{{PpPhase::Pass{pass, 0, {}}}};
            append_ops(phase.passes.front().on_one_processor, per_voxel, voxels);
            work.phases.push_back(Phase{name, std::move(phase)});
        };
        if (pp.classification) voxel_pass("classification", *pp.classification, kWilsonVoxelClassification);
        if (pp.shading) voxel_pass("shading", *pp.shading, kWilsonVoxelShading);
        if (pp.classification || pp.shading) voxel_store_.read_shaded_codes(texels_);
        shaded_for_ = view;
        first_frame_ = false;

        PointLook look;
        look.classification = &frame.classification;
        look.colors = &frame.colors;
        look.lighting = frame.lighting;
        look.view = make_shading_view(camera, volume_.dims(), volume_.spacing());
        HybridFrame slices = slicer_.render(texels_, look, camera, image_.width, image_.height, image_.background);
        work.phases.push_back(Phase{"slicing", std::move(slices.work)});
        work.resident_bits_by_key = resident_bits_by_brick_;
        // New colours in the PPs make the GPs' cached bricks stale.
        work.invalidate_gp_caches = pp.classification.has_value() || pp.shading.has_value();
        work.image_width = image_.width;
        work.image_height = image_.height;
        out->counts = std::move(slices.counts);
        out->paper_thresholds = hybrid_.selection().at_paper_thresholds;
        out->classified = pp.classification.has_value();
        out->shaded = pp.shading.has_value();
        out->compare_passes_with_reference = true;
        out->pass_images.push_back(std::move(slices.low_resolution));
        out->pass_images.push_back(std::move(slices.image));
        return out;
    }

    nlohmann::json frame_stats(const KernelFrame& kernel_frame, const FrameTiming& timing,
                               const std::vector<std::string>& pass_images) const override {
        const auto& frame = static_cast<const WilsonFrame&>(kernel_frame);
        const HybridCounts& c = frame.counts;
        nlohmann::json phases = nlohmann::json::object();
        for (const PhaseTiming& p : timing.phases) phases[p.name + "_seconds"] = seconds(p.duration_ps());
        nlohmann::json sizes = nlohmann::json::object();
        for (const auto& [side, count] : c.point_sizes) sizes[std::to_string(side)] = count;
        nlohmann::json out = {{"simulated_seconds", seconds(timing.duration_ps())},
                              {"phases", phases},
                              {"images", {{"low_resolution", pass_images.at(0)}, {"frame", pass_images.at(1)}}},
                              {"classified", frame.classified},
                              {"reshaded", frame.shaded},
                              {"slice_axis", std::string(1, "xyz"[c.slice_axis])},
                              {"slices", c.slices},
                              {"cells", c.cells},
                              {"quads", c.quads},
                              {"quads_skipped_transparent", c.cells - c.quads - c.cells_behind_eye - c.quads_offscreen},
                              {"cells_behind_eye", c.cells_behind_eye},
                              {"quads_offscreen", c.quads_offscreen},
                              {"quad_draws", c.quad_draws},
                              {"quad_pixels", c.quad_pixels},
                              {"slice_composites", c.slice_composites},
                              {"composited_pixels", c.composited_pixels},
                              {"points", c.points},
                              {"points_drawn", c.points_drawn},
                              {"points_transparent", c.points_transparent},
                              {"points_offscreen", c.points_offscreen},
                              {"point_draws", c.point_draws},
                              {"point_pixels", c.point_pixels},
                              {"point_blocks", c.point_blocks},
                              {"block_pixels", c.block_pixels},
                              {"point_sizes", sizes},
                              {"tasks", c.tasks},
                              {"batches", c.batches},
                              {"batch_words", c.batch_words}};
        if (const PhaseTiming* s = timing.phase("slicing")) out["slicing"] = region_phase_stats(s->gp);
        return out;
    }

    std::string describe(const nlohmann::json& f) const override {
        std::string line =
            fmt::format("; {} slices along {}: {} quads, {} of {} points drawn; {:.1f} ms simulated",
                        f["slices"].dump(), f["slice_axis"].get<std::string>(), f["quads"].dump(),
                        f["points_drawn"].dump(), f["points"].dump(), f["simulated_seconds"].get<double>() * 1e3);
        if (f.contains("slicing"))
            line += fmt::format(" (renderer imbalance {:.2f})", f["slicing"]["renderer_imbalance"].get<double>());
        return line;
    }

    nlohmann::json run_stats() const override {
        const VoxelPlacement& p = voxel_store_.placement();
        const HybridStorage storage = hybrid_.storage();
        const PointSelection& sel = hybrid_.selection();
        const Volume& low = hybrid_.low_resolution();
        const std::uint64_t points_bytes = storage.point_bytes();
        const std::uint64_t low_voxels = static_cast<std::uint64_t>(low.samples().size());
        const std::uint64_t original_voxels = static_cast<std::uint64_t>(volume_.samples().size());
        const nlohmann::json on_machine = {
            {"low_resolution_backing_store_bytes", low_voxels * static_cast<std::uint64_t>(p.record_bits()) / 8},
            {"points_gp_memory_bytes", points_bytes},
            {"points_busiest_gp_bytes", most_point_bytes_},
            {"full_resolution_backing_store_bytes", original_voxels * static_cast<std::uint64_t>(p.record_bits()) / 8},
            {"note",
             "the voxel store's records (Levoy's 8 bytes a voxel with the default layout) for the low-resolution "
             "volume, "
             "against the same records for every voxel of the original (Levoy's kernel); points in the GPs' memory"}};
        return {{"policy", to_string(p.policy())},
                {"on_machine", on_machine},
                {"record_bits", p.record_bits()},
                {"slots_needed", p.slots_needed()},
                {"backing_store_bits_used", p.backing_store_bits_used()},
                {"hybrid",
                 {{"low_resolution", {low.dims().x, low.dims().y, low.dims().z}},
                  {"factor", hybrid_.factor()},
                  {"error_grid", {hybrid_.error_grid().x, hybrid_.error_grid().y, hybrid_.error_grid().z}},
                  {"error_samples", sel.error_samples},
                  {"above_threshold", sel.above_threshold},
                  {"underestimates", sel.underestimates},
                  {"points_at_paper_thresholds",
                   {{"1/64", sel.at_paper_thresholds[0]},
                    {"1/32", sel.at_paper_thresholds[1]},
                    {"1/16", sel.at_paper_thresholds[2]},
                    {"1/12", sel.at_paper_thresholds[3]},
                    {"1/8", sel.at_paper_thresholds[4]}}},
                  {"largest_error", sel.largest_error},
                  {"mean_abs_error", sel.mean_abs_error},
                  {"points", storage.points},
                  {"point_record_bytes", storage.point_format.record_bytes()},
                  {"points_bytes", points_bytes},
                  {"low_resolution_bytes", storage.volume_bytes()},
                  {"total_megabytes", static_cast<double>(storage.total_bytes()) / 1e6},
                  {"original_megabytes",
                   static_cast<double>(HybridStorage{volume_.dims(), storage.voxel_value_bytes,
                                                     storage.voxel_gradient_byte, 0, storage.point_format}
                                           .total_bytes()) /
                       1e6},
                  {"note",
                   "sizes as the paper counts them (section 3.3): a voxel's value and normal index, a point's record; "
                   "MB = 10^6 bytes. On the machine the low-resolution voxels sit in the voxel store's records and "
                   "the points in the memory of the GP owning their brick"}}}};
    }

private:
    // Each GP keeps the points of the bricks it owns (brick b on GP b mod G) besides its cache: refused
    // here, before any frame, when they do not fit, saying what would.
    void check_points_fit(const Machine& machine) {
        const std::size_t gps = machine.gps().size();
        std::vector<std::uint64_t> per_gp(gps, 0);
        for (std::size_t b = 0; b < resident_bits_by_brick_.size(); ++b) per_gp[b % gps] += resident_bits_by_brick_[b];
        const auto most = std::max_element(per_gp.begin(), per_gp.end());
        most_point_bytes_ = (*most + 7) / 8;
        const auto& gp = *machine.gps().front();
        const std::uint64_t cache_bytes = gp.cache_bits() / 8;
        if (most_point_bytes_ + cache_bytes > gp.memory_bytes())
            reject_field(
                "gp.memory_bytes",
                fmt::format(
                    "GP {} must keep {} bytes of points ({} points of {} bytes in all) besides its {} byte cache: "
                    "{} bytes, more than its {}; raise gp.memory_bytes or gp.count, or keep fewer points "
                    "(wilson.error_threshold, wilson.max_points)",
                    most - per_gp.begin(), most_point_bytes_, hybrid_.points().size(),
                    hybrid_.point_format().record_bytes(), cache_bytes, most_point_bytes_ + cache_bytes,
                    gp.memory_bytes()));
    }

    static RegionMachine slice_machine(const Machine& machine, const PpShading& store) {
        const VoxelPlacement* placement = &store.placement();
        return RegionMachine::from(machine, [placement](glm::ivec3 v) { return placement->locate(v).renderer; });
    }

    const Volume& volume_;
    ImageSpec image_;
    WilsonSettings settings_;
    HybridVolume hybrid_;
    PpShading voxel_store_;
    HybridSlicer slicer_;
    Classification classification_;
    ShadedCodes texels_;
    std::optional<ShadingView> shaded_for_;
    bool first_frame_ = true;
    std::vector<std::uint64_t> resident_bits_by_brick_;
    std::uint64_t most_point_bytes_ = 0;
};

class WilsonKernel final : public Kernel {
public:
    std::string name() const override { return "wilson"; }
    std::string description() const override {
        return "Wilson, Ma, McCormick 2002: a low-resolution volume plus points where its reconstruction errs; the PPs "
               "shade the "
               "low-resolution voxels, the GPs turn each slice's texel cells into quads and their points into squares "
               "and bin them "
               "by screen region, the renderers draw the slices back to front with the points between them";
    }
    std::string timing_summary() const override {
        return "event-driven: PP shading passes over the low-resolution voxels, then per slice the GPs' bricks fetched "
               "over the ring "
               "and turned into quad and point batches, drawn by each renderer in back-to-front order from its region "
               "programs' "
               "operations";
    }
    std::vector<const ParamGroup*> param_groups() const override {
        return {&VoxelStoreSettings::placement_params(),
                &VoxelStoreSettings::layout_params(),
                &WilsonSettings::params(),
                &wilson_cost_params(),
                &voxel_store_cost_params(),
                &screen_region_cost_params()};
    }
    bool runs_on_machine() const override { return true; }
    std::size_t most_pictures_per_frame(const MachineConfig&) const override {
        return 2;
    }  // L alone, then with its points
    bool compares_each_picture() const override { return true; }
    void check(const Scenario& scenario) const override {
        const std::string file = scenario.file.string();
        if (scenario.image.resampling != ResamplingOrder::ShadeThenInterpolate)
            throw InputError(file, "image.resampling",
                             "the wilson kernel interpolates shaded texels (shade-then-interpolate)");
        refuse_stationary_lights(scenario, "wilson",
                                 "its GPs shade each error point with one light (gp_cost.wilson.* counts one)");
    }
    std::unique_ptr<KernelRun> start(Machine& machine, const MachineConfig& config, const Scenario& scenario,
                                     const Volume& volume) const override {
        return std::make_unique<WilsonRun>(machine, config, scenario, volume);
    }
    std::vector<KernelMetric> metrics() const override {
        return {{"frame_seconds", "s", "the whole frame: PP passes and slicing"},
                {"slicing_seconds", "s", "the GPs' and renderers' slices and points alone"},
                {"points_drawn", "points", "points with opacity to add, on screen"},
                {"threshold_trend", "ratio",
                 "error samples past 1/64 of the value range over those past 1/12: how fast the point count grows as "
                 "the threshold "
                 "tightens (the paper's chest at 128^3: 10999K / 3979K = 2.76)"}};
    }
    std::vector<KernelFormula> formulas() const override {
        return {{"storage_megabytes",
                 "MB",
                 "the paper's representation of 8-bit data (section 3.3): a value byte and a normal index per "
                 "low-resolution voxel, "
                 "a 6- or 9-byte record per point by the error grid's size; MB = 10^6 bytes",
                 {{"low_resolution", 3}, {"points", 1}, {"error_grid", 3}}},
                {"point_room_millions",
                 "million points",
                 "how many point records fit in the space a lower resolution frees (section 3.3)",
                 {{"original", 3}, {"low_resolution", 3}, {"point_bytes", 1}}}};
    }
    double formula(const std::string& name, const FormulaInputs& inputs) const override {
        const auto dims = [&](const char* key) {
            const std::vector<double>& v = inputs.at(key);
            if (v.size() != 3 ||
                std::any_of(v.begin(), v.end(), [](double x) { return !(x >= 1 && x <= 65536 && x == std::floor(x)); }))
                throw std::domain_error(std::string(key) + " must be three whole sizes from 1 to 65536");
            return glm::ivec3(static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]));
        };
        const auto number = [&](const char* key, double most) {
            const std::vector<double>& v = inputs.at(key);
            if (v.size() != 1 || !(v[0] >= 0 && v[0] <= most))
                throw std::domain_error(fmt::format("{} must be one number from 0 to {}", key, most));
            return v[0];
        };
        if (name == "storage_megabytes") {
            const HybridStorage storage{dims("low_resolution"), 1, false,
                                        static_cast<std::uint64_t>(number("points", 1e12)),
                                        PointFormat::for_grid(dims("error_grid"), 1, false)};
            return static_cast<double>(storage.total_bytes()) / 1e6;
        }
        if (name == "point_room_millions") {
            const double bytes = number("point_bytes", 64);
            if (!(bytes >= 1)) throw std::domain_error("point_bytes must be at least 1");
            const auto volume = [](glm::ivec3 d) { return HybridStorage{d, 1, false, 0, PointFormat{}}.total_bytes(); };
            const std::uint64_t original = volume(dims("original")), low = volume(dims("low_resolution"));
            if (low > original) throw std::domain_error("low_resolution must be no larger than original");
            return static_cast<double>(original - low) / bytes / 1e6;
        }
        return Kernel::formula(name, inputs);
    }
    double metric(const std::string& name, const KernelFrame& kernel_frame, const FrameTiming& timing) const override {
        const auto& frame = static_cast<const WilsonFrame&>(kernel_frame);
        if (name == "frame_seconds") return seconds(timing.duration_ps());
        if (name == "slicing_seconds") {
            const PhaseTiming* s = timing.phase("slicing");
            if (s == nullptr) throw std::domain_error("the frame has no slicing phase");
            return seconds(s->duration_ps());
        }
        if (name == "threshold_trend") {
            const auto& counts = frame.paper_thresholds;
            if (counts[3] == 0) throw std::domain_error("no error sample is past 1/12 of the value range");
            return static_cast<double>(counts[0]) / static_cast<double>(counts[3]);
        }
        if (name == "points_drawn") {
            if (frame.counts.points_drawn == 0) throw std::domain_error("the frame draws no points");
            return static_cast<double>(frame.counts.points_drawn);
        }
        return Kernel::metric(name, kernel_frame, timing);
    }
};

}  // namespace

const Kernel& wilson_kernel() {
    static const WilsonKernel kernel;
    return kernel;
}

}  // namespace pp5
