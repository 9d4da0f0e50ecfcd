#include "kernels/perm/perm_kernel.h"

#include "kernels/perm/perm_costs.h"
#include "kernels/perm/perm_ray_caster.h"
#include "kernels/perm/perm_record_shading.h"
#include "kernels/perm/perm_structure.h"
#include "kernels/shared/pp_volume/pp_shading.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/host_memory.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <glm/vector_relational.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace pp5 {

namespace {

double seconds(Tick t) { return ticks_to_seconds(t); }
std::uint64_t cube_of(int n) {
    return static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n);
}

constexpr int kRecordBrick = 4;  // records are dealt to renderers in 4^3 bricks of cells

struct PermKernelFrame final : KernelFrame {
    PermCastCounts counts;
    bool rebuilt = false;
    bool pp_classified = false;  // perm.shading = pp: which record passes the PPs ran
    bool pp_shaded = false;
};

class PermRun final : public KernelRun {
public:
    PermRun(Machine& machine, const MachineConfig& config, const Scenario& scenario, const Volume& volume)
        : machine_(machine),
          volume_(volume),
          image_(scenario.image),
          scenario_file_(scenario.file.string()),
          settings_(PermSettings::from(config)),
          layout_(VoxelStoreSettings::from(config).layout),
          renderers_(static_cast<std::uint32_t>(machine.shape().renderers)),
          pps_(machine.shape().pps_per_renderer()),
          backing_store_bits_(static_cast<std::uint64_t>(machine.shape().backing_store_bits)),
          renderer_bytes_(static_cast<std::uint64_t>(pps_) * backing_store_bits_ / 8),
          gp_memory_bytes_(machine.shape().gp_memory_bytes) {
        check_reduction(scenario);
        build(scenario.frames.front().classification);
    }

    std::unique_ptr<KernelFrame> record_frame(const FrameSpec& frame) override {
        auto out = std::make_unique<PermKernelFrame>();
        const Camera camera = frame_camera(frame, volume_);
        if (settings_.reduction_cells > 0) {
            const glm::vec3 eye = camera.eye / volume_.spacing();
            if (camera.projection == Projection::Perspective && glm::all(glm::greaterThanEqual(eye, glm::vec3(0.0f))) &&
                glm::all(glm::lessThanEqual(eye, glm::vec3(volume_.dims() - 1))))
                throw InputError(scenario_file_, "camera",
                                 "the eye is inside the volume, where perm.reduction_cells's dropped cells are "
                                 "visible; set it to 0 for this view");
        }
        // The structure depends on which cells may be visible: a new classification rebuilds it (on
        // the host, before the frame, as the paper's preprocessing).
        if (frame.classification != built_for_) {
            build(frame.classification);
            out->rebuilt = true;
        }
        FrameWork& work = out->work;
        work.op_kinds = perm_op_kinds();
        if (shading_) shade_records(frame, camera, *out);
        PermCastSettings cs{image_.width, image_.height, image_.sample_step, image_.termination_opacity,
                            image_.background};
        PermFrame cast = caster_->cast(frame.classification, frame.colors, frame.lighting, camera, cs);
        work.phases.push_back(Phase{"ray_casting", std::move(cast.work)});
        work.gp_resident_bits = gp_resident_bytes() * 8;
        // Records the GPs may hold in their caches changed: a new structure, or fresh PP results.
        work.invalidate_gp_caches = !first_frame_ && (out->rebuilt || out->pp_classified || out->pp_shaded);
        first_frame_ = false;
        work.image_width = image_.width;
        work.image_height = image_.height;
        out->counts = cast.counts;
        out->pass_images.push_back(std::move(cast.image));
        return out;
    }

    nlohmann::json frame_stats(const KernelFrame& kernel_frame, const FrameTiming& timing,
                               const std::vector<std::string>& pass_images) const override {
        const auto& frame = static_cast<const PermKernelFrame&>(kernel_frame);
        const PermCastCounts& c = frame.counts;
        nlohmann::json out = {{"simulated_seconds", seconds(timing.duration_ps())},
                              {"images", {{"frame", pass_images.empty() ? "" : pass_images.back()}}},
                              {"rebuilt", frame.rebuilt},
                              {"rays", c.rays},
                              {"rays_terminated", c.rays_terminated},
                              {"samples", c.samples},
                              {"empty_samples", c.empty_samples},
                              {"leaped_samples", c.leaped_samples},
                              {"cell_fetches", c.cell_fetches},
                              {"carried_lookups", c.carried_lookups},
                              {"gp_resident_bytes", frame.work.gp_resident_bits / 8}};
        if (shading_) {
            nlohmann::json pp = {
                {"classified", frame.pp_classified},
                {"shaded", frame.pp_shaded},
                {"positions", shading_->positions()},
                {"note", "perm.shading = pp: the renderers' PPs classify and shade every record position"}};
            for (const char* pass : {"classification", "shading"})
                if (const PhaseTiming* p = timing.phase(pass))
                    pp[std::string(pass) + "_seconds"] = seconds(p->duration_ps());
            out["pp"] = std::move(pp);
        }
        if (const PhaseTiming* r = timing.phase("ray_casting")) {
            const GpPhaseCounts& g = r->gp;
            out["ray_casting"] = {{"gp_computing_seconds", seconds(g.gp_busy)},
                                  {"gp_waiting_seconds", seconds(g.gp_wait)},
                                  {"ring_busy_seconds", seconds(g.ring_busy)},
                                  {"renderers_answering_seconds", seconds(g.renderer_busy)},
                                  {"note", "GP and ring times are summed over GPs and channels"},
                                  {"fetch_requests", g.fetch_requests},  // a block of records each
                                  {"cache_hits", g.cache_hits},
                                  {"cache_misses", g.cache_misses},
                                  {"events", g.events}};
        }
        return out;
    }

    std::string describe(const nlohmann::json& f) const override {
        return fmt::format("; {} rays, {} samples looked up, {} cells entered; {:.1f} ms simulated", f["rays"].dump(),
                           f["samples"].dump(), f["cell_fetches"].dump(), f["simulated_seconds"].get<double>() * 1e3);
    }

    nlohmann::json run_stats() const override {
        const PermMemory m = structure_->memory();
        return {
            {"perm",
             {{"candidates", m.candidates},
              {"candidates_before_reduction", structure_->candidates_before_reduction()},
              {"cells", static_cast<std::uint64_t>(std::max(0, volume_.dims().x - 1)) *
                            static_cast<std::uint64_t>(std::max(0, volume_.dims().y - 1)) *
                            static_cast<std::uint64_t>(std::max(0, volume_.dims().z - 1))},
              {"density_positions", m.density_positions},
              {"gradient_positions", m.gradient_positions},
              {"record_bytes", m.record_bytes()},
              {"index_volume_bytes", m.index_volume_bytes()},
              {"summed_table_bytes", m.summed_table_bytes()},
              {"records_bytes", m.candidates * m.record_bytes()},
              {"total_megabytes", static_cast<double>(m.total_bytes()) / 1e6},
              {"residence", settings_.residence == PermResidence::GpMemory ? "gp_memory" : "renderers"},
              {"shading", shading_ ? "pp" : "gp"},
              {"busiest_renderer_bytes", busiest_renderer_bytes_},
              {"busiest_renderer_bits_per_pp", busiest_renderer_bits_per_pp_},
              {"build",
               {{"host_seconds", build_seconds_}, {"note", "the structure made on this computer, before the frames"}}},
              {"note",
               "eqs. (3) and (6): the index volume (with a 4-byte summed count per z slice at 2-byte indices) and "
               "N_cc records of D^3 density bytes and G^3 x (3 gradient bytes + a sign byte); MB = 10^6 bytes. With "
               "perm.shading = pp the renderers hold each record as D^3 voxel slots of voxel_store.* bits instead"}}}};
    }

private:
    // perm.shading = pp: the PPs classify the records after a rebuild, and reshade them when the
    // colours or the light change, or the view when the shading depends on it (the depth cue, which
    // the GPs apply, does not count).
    void shade_records(const FrameSpec& frame, const Camera& camera, PermKernelFrame& out) {
        const PhongLighting on_pps = PermRecordShading::lighting_on_pps(frame.lighting);
        const glm::vec3 forward = camera.forward();
        const bool classify = first_frame_ || out.rebuilt;
        const bool reshade = classify || frame.colors != shaded_colors_ || on_pps != shaded_lighting_ ||
                             (shading_depends_on_view(on_pps) && forward != shaded_forward_);
        const auto pass = [&](const char* name, PpPassWork work, PermOp per_position) {
            PpPhase phase{{PpPhase::Pass{std::move(work), 0, {}}}};
            append_ops(phase.passes.front().on_one_processor, per_position, shading_->positions());
            out.work.phases.push_back(Phase{name, std::move(phase)});
        };
        if (classify) pass("classification", shading_->classify(frame.classification), kPermPositionClassification);
        if (reshade) {
            pass("shading", shading_->shade(frame.colors, frame.lighting, forward), kPermPositionShading);
            shading_->read_back();
            shaded_colors_ = frame.colors;
            shaded_lighting_ = on_pps;
            shaded_forward_ = forward;
        }
        out.pp_classified = classify;
        out.pp_shaded = reshade;
    }

    // The reduction leaves pictures unchanged only if a ray crossing t_e - 2 opaque cells (a diagonal
    // ray may skip a sample in a cell at each end) has reached the termination opacity.
    void check_reduction(const Scenario& scenario) const {
        if (settings_.reduction_cells == 0) return;
        const double stop = scenario.image.termination_opacity;
        const double alpha = settings_.reduction_opacity;
        const double needed = stop < 1 && alpha < 1 ? 2 + std::log(1 - stop) / std::log(1 - alpha) : 2;
        if (stop >= 1 || settings_.reduction_cells < std::ceil(needed))
            reject_field(
                "perm.reduction_cells",
                stop >= 1
                    ? std::string(
                          "rays never terminate early (image.termination_opacity = 1), so no cell can be dropped")
                    : fmt::format(
                          "{} cells of opacity {} bring a ray to {:.3f}, short of its termination at {}; use at "
                          "least {} (or raise perm.reduction_opacity)",
                          settings_.reduction_cells - 2, alpha, 1 - std::pow(1 - alpha, settings_.reduction_cells - 2),
                          scenario.image.termination_opacity, std::ceil(needed)));
    }

    std::uint32_t renderer_of_cell(glm::ivec3 origin) const {
        const glm::ivec3 b = origin / kRecordBrick;
        const glm::ivec3 n = (volume_.dims() + kRecordBrick - 1) / kRecordBrick;
        return static_cast<std::uint32_t>((b.x + n.x * (b.y + n.y * b.z)) % static_cast<int>(renderers_));
    }

    void build(const Classification& classification) {
        const auto started = std::chrono::steady_clock::now();
        caster_.reset();
        shading_.reset();
        // Refused before any record is made when it cannot fit where it is to live.
        const auto fits = [this](const PermMemory& m, const std::vector<glm::ivec3>& origins) {
            check_fit(m, origins);
        };
        structure_ = std::make_unique<PermStructure>(PermStructure::build(volume_, classification, settings_, fits));
        if (settings_.shading == PermShading::Pp)
            shading_ = std::make_unique<PermRecordShading>(
                machine_, *structure_, volume_.spacing(), layout_,
                [this](std::uint32_t c) { return renderer_of_cell(structure_->cell_origin(c)); });
        build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        built_for_ = classification;
        caster_ = std::make_unique<PermRayCaster>(
            *structure_, volume_.spacing(), settings_,
            settings_.residence == PermResidence::Renderers
                ? std::function<std::uint32_t(glm::ivec3)>([this](glm::ivec3 o) { return renderer_of_cell(o); })
                : std::function<std::uint32_t(glm::ivec3)>(),
            shading_.get());
    }

    void check_fit(const PermMemory& m, const std::vector<glm::ivec3>& origins) {
        // The host holds the records too (the pictures come from them). Density is kept as 16 bits; PP
        // results as four 16-bit codes a position.
        const std::uint64_t pp_results = settings_.shading == PermShading::Pp ? 8 * cube_of(m.density_positions) : 0;
        const std::uint64_t host_bytes =
            m.candidates * (m.record_bytes() + 2 * cube_of(m.density_positions) + pp_results);
        check_fits_host_memory(
            "", "perm.density_positions", static_cast<double>(host_bytes),
            fmt::format("holding {} candidate cells of {} bytes (quantize more coarsely: perm.density_positions, "
                        "perm.gradient_positions)",
                        m.candidates, m.record_bytes()));
        std::vector<std::uint64_t> per(renderers_, 0);
        for (const glm::ivec3& o : origins) ++per[renderer_of_cell(o)];
        const std::uint64_t busiest = per.empty() ? 0 : *std::max_element(per.begin(), per.end());
        busiest_renderer_bytes_ = busiest * m.record_bytes();
        busiest_renderer_bits_per_pp_ =
            settings_.shading == PermShading::Pp
                ? PermRecordShading::backing_store_bits_needed(busiest * cube_of(m.density_positions), pps_, layout_)
                : (busiest_renderer_bytes_ * 8 + static_cast<std::uint64_t>(pps_) - 1) /
                      static_cast<std::uint64_t>(pps_);
        if (settings_.shading == PermShading::Pp && busiest_renderer_bits_per_pp_ > backing_store_bits_)
            reject_field(
                "renderer.backing_store_bits",
                fmt::format(
                    "PERM's records shaded on the PPs need {} bits per PP on the busiest renderer ({} records of {} "
                    "positions, {} bits each) but a PP holds {}; quantize the density more coarsely "
                    "(perm.density_positions), add renderers (renderer.count) or backing store, or shade on the "
                    "GPs (perm.shading = \"gp\")",
                    busiest_renderer_bits_per_pp_, busiest, cube_of(m.density_positions), layout_.bits(),
                    backing_store_bits_));
        if (settings_.residence == PermResidence::GpMemory && m.total_bytes() > gp_memory_bytes_)
            reject_field(
                "gp.memory_bytes",
                fmt::format(
                    "a copy of PERM in every GP needs {} bytes ({} candidate cells of {} bytes and the index "
                    "volume), more than a GP's {}; use perm.residence = \"renderers\" or quantize more coarsely",
                    m.total_bytes(), m.candidates, m.record_bytes(), gp_memory_bytes_));
        if (settings_.residence == PermResidence::Renderers && busiest_renderer_bytes_ > renderer_bytes_)
            reject_field(
                "renderer.backing_store_bits",
                fmt::format(
                    "PERM's records need {} bytes on the busiest renderer ({} candidate cells of {} bytes, {:.1f} MB "
                    "in all) but a renderer's PPs hold {} bytes; quantize more coarsely (perm.density_positions, "
                    "perm.gradient_positions), add renderers (renderer.count) or backing store",
                    busiest_renderer_bytes_, m.candidates, m.record_bytes(), static_cast<double>(m.total_bytes()) / 1e6,
                    renderer_bytes_));
        // Records the GPs fetch from the renderers' backing store are placed data there, in the same
        // books as the voxel store's (PermRecordShading counts its own layout when the PPs shade).
        if (settings_.residence == PermResidence::Renderers && settings_.shading == PermShading::Gp) {
            auto& renderers = machine_.renderers();
            for (std::size_t r = 0; r < renderers.size() && r < per.size(); ++r)
                renderers[r]->set_backing_store_bits_used(
                    (per[r] * m.record_bytes() * 8 + static_cast<std::uint64_t>(pps_) - 1) /
                    static_cast<std::uint64_t>(pps_));
        }
    }

    // What each GP keeps besides its cache: the distance map and the index volume that finds a sample's
    // record (with its per-slice summed table), and the records too when they live in GP memory.
    std::uint64_t gp_resident_bytes() const {
        const PermMemory& m = structure_->memory();
        const std::uint64_t records =
            settings_.residence == PermResidence::GpMemory ? m.candidates * m.record_bytes() : 0;
        return caster_->distance_map_bytes() + m.index_volume_bytes() + m.summed_table_bytes() + records;
    }

    Machine& machine_;
    const Volume& volume_;
    ImageSpec image_;
    std::string scenario_file_;
    PermSettings settings_;
    VoxelRecordLayout layout_;
    std::uint32_t renderers_;
    int pps_;
    std::uint64_t backing_store_bits_;
    std::uint64_t renderer_bytes_;
    std::uint64_t gp_memory_bytes_;
    std::unique_ptr<PermStructure> structure_;
    std::unique_ptr<PermRecordShading> shading_;  // perm.shading = pp
    std::unique_ptr<PermRayCaster> caster_;
    Classification built_for_;
    bool first_frame_ = true;
    ColorMap shaded_colors_;  // what the PPs' results were shaded for
    PhongLighting shaded_lighting_;
    glm::vec3 shaded_forward_{0.0f};
    std::uint64_t busiest_renderer_bytes_ = 0;
    std::uint64_t busiest_renderer_bits_per_pp_ = 0;
    double build_seconds_ = 0;
};

class PermKernel final : public Kernel {
public:
    std::string name() const override { return "perm"; }
    std::string description() const override {
        return "Lim and Shin: PERM, each candidate cell's density and gradient precomputed at quantized positions; the "
               "GPs cast "
               "rays, fetch each cell's record through their caches and classify, shade and composite from the "
               "looked-up values "
               "(or, with perm.shading = pp, read what the renderers' PPs classified and shaded at every record "
               "position)";
    }
    std::string timing_summary() const override {
        return "event-driven: the GPs' rays, each sample's look-up and shading on the GP (or the PPs' classification "
               "and shading "
               "passes over the records first), each cell's record fetched over the ring through the GP cache";
    }
    std::vector<const ParamGroup*> param_groups() const override {
        return {&PermSettings::params(), &VoxelStoreSettings::layout_params(), &perm_cost_params()};
    }
    bool runs_on_machine() const override { return true; }
    void check(const Scenario& scenario) const override {
        const std::string file = scenario.file.string();
        if (scenario.image.resampling != ResamplingOrder::InterpolateThenShade)
            throw InputError(file, "image.resampling",
                             "the perm kernel classifies and shades each sample (interpolate-then-shade)");
        refuse_stationary_lights(scenario, "perm",
                                 "its GPs shade each sample with one light (gp_cost.perm.* counts one)");
    }
    std::unique_ptr<KernelRun> start(Machine& machine, const MachineConfig& config, const Scenario& scenario,
                                     const Volume& volume) const override {
        return std::make_unique<PermRun>(machine, config, scenario, volume);
    }
    std::vector<KernelMetric> metrics() const override {
        return {{"frame_seconds", "s", "the whole frame: the GPs' ray casting"}};
    }
    double metric(const std::string& name, const KernelFrame& frame, const FrameTiming& timing) const override {
        if (name == "frame_seconds") return seconds(timing.duration_ps());
        return Kernel::metric(name, frame, timing);
    }
    std::vector<KernelFormula> formulas() const override {
        return {{"memory_megabytes",
                 "MB",
                 "eqs. (3) and (6): the index volume (with a 4-byte summed count per z slice at 2-byte indices) and "
                 "the candidates' "
                 "records; MB = 10^6 bytes",
                 {{"dims", 3},
                  {"candidates", 1},
                  {"density_positions", 1},
                  {"gradient_positions", 1},
                  {"index_bytes", 1},
                  {"density_bytes", 1}}}};
    }
    double formula(const std::string& name, const FormulaInputs& inputs) const override {
        if (name != "memory_megabytes") return Kernel::formula(name, inputs);
        const auto whole = [&](const char* key, double lo, double hi) {
            const std::vector<double>& v = inputs.at(key);
            for (const double x : v)
                if (!(x >= lo && x <= hi && x == std::floor(x)))
                    throw std::domain_error(fmt::format("{} must be whole numbers from {} to {}", key, lo, hi));
            return v;
        };
        const std::vector<double> dims = whole("dims", 1, 65536);
        if (dims.size() != 3) throw std::domain_error("dims must be three sizes");
        const auto one = [&](const char* key, double lo, double hi) {
            const std::vector<double> v = whole(key, lo, hi);
            if (v.size() != 1) throw std::domain_error(std::string(key) + " must be one number");
            return static_cast<int>(v[0]);
        };
        PermMemory m;
        m.dims = glm::ivec3(static_cast<int>(dims[0]), static_cast<int>(dims[1]), static_cast<int>(dims[2]));
        m.candidates = static_cast<std::uint64_t>(whole("candidates", 0, 1e12).at(0));
        m.density_positions = one("density_positions", 1, 64);
        m.gradient_positions = one("gradient_positions", 1, 64);
        m.index_bytes = one("index_bytes", 1, 8);
        m.density_bytes = one("density_bytes", 1, 8);
        return static_cast<double>(m.total_bytes()) / 1e6;
    }
};

}  // namespace

const Kernel& perm_kernel() {
    static const PermKernel kernel;
    return kernel;
}

}  // namespace pp5
