#include "kernels/levoy/levoy_renderer.h"

#include "kernels/levoy/geometry_programs.h"
#include "kernels/levoy/polygon_candidates.h"
#include "kernels/levoy/ray_cast_work.h"
#include "kernels/levoy/ray_caster.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"
#include "sim/core/work_progress.h"
#include "sim/timing/frame_engine.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace pp5 {

namespace {
int voxel_bits_of(const VoxelRecordLayout& layout) { return 3 * layout.color_bits + layout.opacity_bits; }
}  // namespace

void LevoyRenderer::check_fits(const Machine& machine, glm::ivec3 dims, const LevoySettings& settings) {
    try {
        PpShading::check_fits(machine, dims, settings.store);
    } catch (const InputError& refusal) {
        // Say so when only the stationary lights' field stands in the way: it is the one to give up.
        VoxelStoreSettings without = settings.store;
        without.layout.stationary_light_bits = 0;
        if (settings.store.layout.stationary_light_bits == 0) throw;
        PpShading::check_fits(machine, dims, without);  // refuses as before when even that cannot fit
        throw InputError(
            refusal.file(), "levoy.stationary_light_bits",
            fmt::format("the stationary lights' precomputed sum takes a voxel's record from {} to {} bits, and then: "
                        "{}; set levoy.stationary_light_bits=0 to recompute every light at each reshade instead",
                        without.layout.bits(), settings.store.layout.bits(), refusal.reason()));
    }
    // Every frame's GPs hold the whole pyramid (a bit a cell) beside their caches.
    const bool any_axis_too_thin = dims.x < 2 || dims.y < 2 || dims.z < 2;  // the pyramid refuses these itself
    check_gp_memory_fits(machine, true,
                         settings.pyramid_skipping && !any_axis_too_thin ? BinaryPyramid::total_cells_of(dims) : 0);
}

LevoyRenderer::LevoyRenderer(Machine& machine, const Volume& volume, const LevoySettings& settings,
                             const LevoyImageSettings& image)
    : machine_(machine),
      settings_(settings),
      image_(image),
      dims_((check_fits(machine, volume.dims(), settings), volume.dims())),
      spacing_(volume.spacing()),
      pixel_processors_(machine, volume, settings.store),
      blocks_(pixel_processors_.placement(), settings.block_cells, voxel_bits_of(settings.store.layout)),
      directory_(blocks_.directory()) {
    if (image.width < 1 || image.height < 1)
        throw InputError("scenario", "image.width", "the image needs at least one pixel");
    for (auto& gp : machine.gps())
        gp->cache(blocks_.block_bits());  // InputError if one block does not fit, before any frame
    depth_.assign(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height), 0);
}

namespace {

void add_op(std::vector<GpOp>& ops, LevoyOp kind, std::uint64_t count) { append_ops(ops, kind, count); }

PpProgramPass pass_of(const PhaseTiming* phase) {
    return phase != nullptr && !phase->passes.empty() ? PpProgramPass(phase->passes.front()) : PpProgramPass();
}

}  // namespace

LevoyFrameTiming levoy_frame_timing(const LevoyFrameWork& work, const FrameTiming& timing) {
    LevoyFrameTiming t;
    t.start_ps = timing.start_ps;
    t.end_ps = timing.end_ps;
    const PhaseTiming* classification = timing.phase("classification");
    const PhaseTiming* stationary = timing.phase("stationary_lights");
    const PhaseTiming* shading = timing.phase("shading");
    t.pixel_processors.classification = pass_of(classification);
    t.pixel_processors.stationary_lights = pass_of(stationary);
    t.pixel_processors.shading = pass_of(shading);
    // The PP passes run one after another in this order; the first that ran starts them.
    const PhaseTiming* first = classification ? classification : stationary ? stationary : shading;
    const PhaseTiming* last = shading ? shading : stationary ? stationary : classification;
    t.pixel_processors.start_ps = first ? first->start_ps : timing.start_ps;
    t.pixel_processors.end_ps = last ? last->end_ps : timing.start_ps;
    t.region = pass_of(timing.phase("region_of_interest"));
    // A frame that scan-converts records the phase, even when every polygon is degenerate.
    if (const PhaseTiming* scan = timing.phase("scan_conversion")) {
        t.geometry.ran = true;
        t.geometry.polygons = work.polygons;
        t.geometry.start_ps = scan->start_ps;
        t.geometry.end_ps = scan->end_ps;
        for (const PpPassTiming& p : scan->passes) t.geometry.slots += p.slots;
    }
    if (const PhaseTiming* pyramid = timing.phase("pyramid")) t.pyramid_ps = pyramid->duration_ps();
    RayCastReport& rc = t.ray_cast;
    if (const PhaseTiming* cast = timing.phase("ray_casting")) {
        rc.start = cast->start_ps;
        rc.end = cast->end_ps;
        rc.pass_end = cast->group_end_ps;
        rc.cache_hits = cast->gp.cache_hits;
        rc.cache_misses = cast->gp.cache_misses;
        rc.fetch_requests = cast->gp.fetch_requests;
        rc.blocks_refreshed = cast->gp.blocks_refreshed;
        rc.context_switches = cast->gp.context_switches;
        rc.gp_busy = cast->gp.gp_busy;
        rc.gp_wait = cast->gp.gp_wait;
        rc.renderer_busy = cast->gp.renderer_busy;
        rc.ring_busy = cast->gp.ring_busy;
        rc.events = cast->gp.events;
    }
    static_cast<RayCastCounts&>(rc) = work.rays;
    return t;
}

LevoyFrameTiming time_levoy_frame(Machine& machine, const LevoyFrameWork& work) {
    return levoy_frame_timing(work, time_frame(machine, work.machine));
}

// Every renderer broadcasts one bit per voxel it holds, a slot at a time; every GP takes every message
// in and, with all of them, builds the whole pyramid.
Phase LevoyRenderer::pyramid_phase() const {
    const VoxelPlacement& placement = pixel_processors_.placement();
    BroadcastPhase broadcast;
    for (std::size_t r = 0; r < machine_.renderers().size(); ++r)
        broadcast.messages_per_renderer.push_back(
            static_cast<std::uint32_t>(placement.slots_used(static_cast<int>(r))));
    broadcast.bits_per_message =
        static_cast<std::uint64_t>(placement.shape().columns) * static_cast<std::uint64_t>(placement.shape().rows);
    add_op(broadcast.then_each_gp, kPyramidBuildCell, pyramid_.total_cells());
    return Phase{"pyramid", std::move(broadcast)};
}

// Levoy's Figure 6: the shading pass, with the region's transition zone shaded as if the region held
// air. The region's box coordinates follow the shading's own QEE expressions. A stationary-light sum
// the record keeps is made with the same capped gradients, afresh when the region moved.
LevoyRenderer::CappedShading LevoyRenderer::capped_shading(const LevoyFrameInputs& frame, const ShadingView& view,
                                                           bool region_moved) {
    const RegionOfInterest& region = *frame.region;
    const PpProgramInputs inputs = pixel_processors_.program_inputs();
    const GradientRewrite cap = region_cap(region, dims_, inputs, kShadingExpressions);
    const auto expressions = [&](const SlotFrame& slot) {
        const auto shading = slot_expressions(view, slot, spacing_);
        std::vector<QeeCoefficients> all(shading.begin(), shading.end());
        for (const QeeCoefficients& e : region_expressions(region, slot)) all.push_back(e);
        return all;
    };
    CappedShading out;
    out.stationary_lights =
        pixel_processors_.refresh_stationary_lights(frame.lighting, view, cap, expressions, region_moved);
    const PpProgram program = build_shading_program(frame.colors, frame.lighting, view, inputs, cap);
    out.shading = pixel_processors_.execute(
        program, [](const SlotFrame&) { return true; }, expressions);
    return out;
}

void LevoyRenderer::set_polygons(const std::vector<PolygonSpec>& polygons) {
    polygons_.clear();
    polygon_areas_.clear();
    // Within a voxel of the volume's samples: where a sample's sheet can reach a voxel.
    const glm::dvec3 lower(-1.0), upper = glm::dvec3(dims_);
    for (const PolygonSpec& p : polygons) {
        polygons_.push_back(prepare_polygon(p));
        polygon_areas_.push_back(area_inside_box(p.vertices, lower, upper));
    }
    polygons_changed_ = true;
}

// The host broadcasts each polygon's QEE coefficients; each renderer runs the polygons in the order
// they arrive. A sequential scan-converter visits levoy.scan_voxels_per_area voxels per unit of the
// polygon's area and tests each of its J sample points against the plane and every edge.
Phase LevoyRenderer::scan_convert() {
    const std::vector<glm::dvec3> offsets = subvoxel_offsets(settings_.jitter_samples);
    const PpProgramInputs inputs = pixel_processors_.program_inputs();
    const VoxelPlacement& placement = pixel_processors_.placement();
    PpPhase phase;
    // The controller runs one program per polygon; polygons of one shape run the same one.
    std::map<PolygonProgramShape, std::shared_ptr<const PpProgram>> programs;
    for (std::size_t k = 0; k < polygons_.size(); ++k) {
        const PreparedPolygon& polygon = polygons_[k];
        if (polygon.degenerate) continue;
        const PolygonProgramShape shape =
            polygon_program_shape(polygon, settings_.jitter_samples, dims_, inputs.layout);
        std::shared_ptr<const PpProgram>& shared = programs[shape];
        if (!shared) shared = std::make_shared<const PpProgram>(build_polygon_program(shape, inputs));
        const PpProgram& program = *shared;
        // D, E and F of every expression, a word each.
        const auto bits = static_cast<std::uint64_t>(program.expressions) * 3 * 32;
        PpPhase::Pass pass{
            pixel_processors_.execute(
                shared,
                [&](const SlotFrame& frame) { return polygon_reaches_slot(polygon, frame, dims_, placement.shape()); },
                [&](const SlotFrame& frame) {
                    return polygon_expressions(polygon, offsets, frame, settings_.store.layout);
                },
                [&](const SlotFrame&, std::span<const QeeCoefficients> expressions, std::vector<int>& candidates) {
                    polygon_candidates(polygon, settings_.jitter_samples, program, expressions, placement.shape(),
                                       candidates);
                }),
            bits,
            {}};
        const auto visited =
            static_cast<std::uint64_t>(std::llround(settings_.scan_voxels_per_area * polygon_areas_[k]));
        const auto tests = static_cast<std::uint64_t>(settings_.jitter_samples) * (polygon.edge_normals.size() + 1);
        add_op(pass.on_one_processor, kPolygonPointTest, visited * tests);
        add_op(pass.on_one_processor, kVoxelMatte, visited);
        phase.passes.push_back(std::move(pass));
        report_work("scan-converting polygons", k + 1, polygons_.size());
    }
    return Phase{"scan_conversion", std::move(phase)};
}

// The GPs' work: a task per tile and refinement pass (its rays, in the order the tile casts them; the
// refinement tests that chose them first; filling and sending the tile's pixels last), a group per pass.
// A ray is an item whose steps are the samples and pyramid steps up to each block it looks up.
Phase LevoyRenderer::cast_frame(const Camera& camera, LevoyFrameReport& report) {
    const ScreenTiles tiles(image_.width, image_.height, settings_.tile_pixels);
    RayCastSettings cast_settings;
    cast_settings.width = image_.width;
    cast_settings.height = image_.height;
    cast_settings.sample_step = image_.sample_step;
    cast_settings.early_termination = image_.termination_opacity < 1.0f;
    cast_settings.termination_opacity = image_.termination_opacity;
    cast_settings.background = image_.background;
    cast_settings.pyramid_skipping = settings_.pyramid_skipping;
    const RayCaster caster(shaded_, pyramid_, blocks_, camera, cast_settings);
    AdaptiveRefinement refinement(image_.width, image_.height, settings_.refinement);

    GpPhase job;
    job.assignment = settings_.ray_assignment;
    job.blocks = directory_;
    RayWorkRecorder recorder(tiles, settings_.interleave_tiles, job, report.work.rays);
    std::vector<std::uint32_t> cast_in_tile(static_cast<std::size_t>(tiles.count()), 0);
    std::vector<std::uint32_t> slot_of(static_cast<std::size_t>(image_.width) * static_cast<std::size_t>(image_.height),
                                       0);
    while (!refinement.finished()) {
        const int pass = refinement.passes_recorded();
        const std::vector<std::uint32_t>& pending = refinement.pending();
        const TileOrder order = order_by_tile(tiles, pending);
        CastBatch batch = caster.cast(order.pixels, settings_.depth_buffer ? std::span<const std::uint32_t>(depth_)
                                                                           : std::span<const std::uint32_t>());
        for (std::size_t i = 0; i < pending.size(); ++i) slot_of[pending[i]] = static_cast<std::uint32_t>(i);
        std::vector<glm::vec4> colors(pending.size());
        const bool keep_depth = settings_.depth_buffer && settings_.pyramid_skipping;
        pp5::parallel_for(std::size_t{0}, order.pixels.size(), [&](std::size_t i) {
            colors[slot_of[order.pixels[i]]] = batch.colors[i];
            if (keep_depth) depth_[batch.rays[i].pixel] = batch.rays[i].first_sample;
        });
        const std::vector<std::uint32_t> tests = tests_per_tile(tiles, refinement);
        std::vector<std::uint32_t> filled(static_cast<std::size_t>(tiles.count()));
        for (int t = 0; t < tiles.count(); ++t) {
            const auto tile = static_cast<std::size_t>(t);
            cast_in_tile[tile] += order.first[tile + 1] - order.first[tile];
            filled[tile] = tiles.pixels_in(t) - cast_in_tile[tile];
        }
        RefinementPassReport pass_report;
        pass_report.rays = order.pixels.size();
        pass_report.samples = recorder.add_pass(static_cast<std::uint32_t>(pass), batch, order, tests, filled);
        refinement.record(colors);
        pass_report.pixels_cast = refinement.pixels_cast();
        pass_report.image = refinement.image();
        report.passes.push_back(std::move(pass_report));
        job.groups = static_cast<std::uint32_t>(pass) + 1;
    }
    // The last decision, that nothing more splits, was made too: charge its tests to the last pass.
    if (job.groups > 0 && !refinement.tested_squares().empty()) {
        const std::vector<std::uint32_t> tests = tests_per_tile(tiles, refinement);
        for (int t = 0; t < tiles.count(); ++t)
            if (tests[static_cast<std::size_t>(t)] > 0)
                recorder.add_task(job.groups - 1, t, static_cast<std::uint32_t>(job.items.size()),
                                  tests[static_cast<std::size_t>(t)], 0);
    }
    return Phase{"ray_casting", std::move(job)};
}

LevoyFrameReport LevoyRenderer::render(const LevoyFrameInputs& frame) {
    LevoyFrameReport report = record(frame);
    apply_timing(report, time_levoy_frame(machine_, report.work));
    return report;
}

void apply_timing(LevoyFrameReport& report, const LevoyFrameTiming& timing) {
    static_cast<LevoyFrameTiming&>(report) = timing;
    for (std::size_t p = 0; p < report.passes.size() && p < timing.ray_cast.pass_end.size(); ++p)
        report.passes[p].end_ps = timing.ray_cast.pass_end[p] - report.start_ps;
}

LevoyRenderer::FrameChanges LevoyRenderer::what_changes(const LevoyFrameInputs& frame) {
    FrameChanges c;
    // Shade only for a view the colours depend on; otherwise keep the view they were shaded for.
    c.view = make_shading_view(frame.camera, dims_, spacing_);
    if (shaded_for_ && !shading_depends_on_view(frame.lighting)) c.view = *shaded_for_;
    // A moved region of interest needs fresh opacities (classification) but no new colours, unless it
    // caps (its transition zone's colours follow it), or stopped capping.
    c.region_moved = frame.region != region_;
    c.capping = frame.region && frame.region->cap;
    c.classify = first_frame_ || frame.classification_changed || c.region_moved;
    c.reshade = first_frame_ || frame.classification_changed || frame.lighting_changed || shaded_for_ != c.view ||
                (c.region_moved && (c.capping || (region_ && region_->cap)));
    if (!polygons_.empty() && (c.classify || c.reshade || polygons_changed_))
        c.classify = c.reshade = true;  // matte into fresh voxels
    polygons_changed_ = false;
    return c;
}

// The pyramid of the fresh opacities (with `unscaled`'s, before a region scaled them), kept only if
// its cells differ; then the machine rebuilds it: the PPs mark emptiness (inserted before the
// passes after `emptiness_at`), the GPs build the levels.
void LevoyRenderer::rebuild_pyramid(const ShadedCodes* unscaled, const std::optional<PpPassWork>& emptiness,
                                    std::size_t emptiness_at, LevoyFrameReport& report) {
    FrameWork& machine_work = report.work.machine;
    BinaryPyramid fresh = BinaryPyramid::from_opacity(shaded_, unscaled);
    if (!first_frame_ && fresh.same_cells(pyramid_)) return;
    pyramid_ = std::move(fresh);
    depth_for_.reset();
    // Without skipping the GPs never consult the pyramid, so the machine builds none.
    if (!emptiness) return;
    report.pyramid_rebuilt = true;
    // The level-0 bits are part of the build a lone processor charges per cell.
    machine_work.phases.insert(machine_work.phases.begin() + static_cast<std::ptrdiff_t>(emptiness_at),
                               Phase{"emptiness", PpPhase{{PpPhase::Pass{*emptiness, 0, {}}}}});
    machine_work.phases.push_back(pyramid_phase());
}

Phase LevoyRenderer::voxel_pass(const char* name, const PpPassWork& pass, LevoyOp per_voxel,
                                std::uint64_t per_voxel_count) const {
    const std::uint64_t voxels =
        static_cast<std::uint64_t>(dims_.x) * static_cast<std::uint64_t>(dims_.y) * static_cast<std::uint64_t>(dims_.z);
    PpPhase phase{{PpPhase::Pass{pass, 0, {}}}};
    add_op(phase.passes.front().on_one_processor, per_voxel, voxels * per_voxel_count);
    return Phase{name, std::move(phase)};
}

void LevoyRenderer::record_shading(const LevoyFrameInputs& frame, const FrameChanges& changes, FrameWork& work) {
    // A lone processor shades a voxel once per light it computes: the stationary lights' terms cost it
    // what the key light's do, in their own pass when kept, else in every shading.
    const std::uint64_t stationary_lights = frame.lighting.stationary_lights.size();
    const bool stationary_kept = settings_.store.layout.stationary_light_bits > 0;
    const std::uint64_t lights_per_shading = 1 + (stationary_kept ? 0 : stationary_lights);
    const PpFrameWork pp = pixel_processors_.compute(frame.classification, frame.colors, frame.lighting, changes.view,
                                                     changes.classify, changes.reshade && !changes.capping);
    if (pp.classification)
        work.phases.push_back(voxel_pass("classification", *pp.classification, kVoxelClassification));
    const auto stationary_pass = [&](const PpPassWork& pass) {
        work.phases.push_back(voxel_pass("stationary_lights", pass, kVoxelShading, stationary_lights));
    };
    if (pp.stationary_lights) stationary_pass(*pp.stationary_lights);
    if (pp.shading) work.phases.push_back(voxel_pass("shading", *pp.shading, kVoxelShading, lights_per_shading));
    if (changes.reshade && changes.capping) {
        const CappedShading capped = capped_shading(frame, changes.view, changes.region_moved);
        if (capped.stationary_lights) stationary_pass(*capped.stationary_lights);
        work.phases.push_back(voxel_pass("shading", capped.shading, kVoxelShading, lights_per_shading));
    }
}

LevoyFrameReport LevoyRenderer::record(const LevoyFrameInputs& frame) {
    LevoyFrameReport report;
    LevoyFrameWork& work = report.work;
    FrameWork& machine_work = work.machine;
    machine_work.op_kinds = levoy_op_kinds();
    machine_work.image_width = image_.width;
    machine_work.image_height = image_.height;
    // Function first: what this frame changes, and the work that follows from it.
    const FrameChanges changes = what_changes(frame);
    const ShadingView& view = changes.view;
    const bool classify = changes.classify, reshade = changes.reshade;
    record_shading(frame, changes, machine_work);
    // Fresh opacities may empty or fill voxels: the PPs mark each voxel's emptiness before the region
    // scales them (the pyramid is of the classification's opacities), charged only if the pyramid is rebuilt.
    std::optional<PpPassWork> emptiness;
    const std::size_t emptiness_at = machine_work.phases.size();
    if (classify && settings_.pyramid_skipping) {
        emptiness = pixel_processors_.execute(
            build_emptiness_program(pixel_processors_.program_inputs()), [](const SlotFrame&) { return true; },
            [](const SlotFrame&) { return std::vector<QeeCoefficients>{}; });
    }
    shaded_for_ = view;
    region_ = frame.region;
    // The pyramid marks what the classification leaves non-empty before the region scales it: a
    // superset of what is non-empty after (so skipping stays exact), which a moving region does not
    // change even where its scaling rounds small opacities to zero.
    std::optional<ShadedCodes> unscaled;
    if (classify && region_) {
        pixel_processors_.read_shaded_codes(unscaled.emplace());
        const PpProgram program = build_region_program(*region_, dims_, pixel_processors_.program_inputs());
        const RegionOfInterest& region = *region_;
        const PpPassWork pass = pixel_processors_.execute(
            program, [](const SlotFrame&) { return true; },
            [&](const SlotFrame& f) { return region_expressions(region, f); });
        machine_work.phases.push_back(voxel_pass("region_of_interest", pass, kVoxelRegion));
    }
    if (!polygons_.empty() && reshade) {
        work.polygons = polygons_.size();
        machine_work.phases.push_back(scan_convert());
    }
    if (classify || reshade) {
        pixel_processors_.read_shaded_codes(shaded_);
        machine_work.refresh_gp_caches = !first_frame_ && settings_.refresh_caches;
        machine_work.refresh_blocks_per_message = static_cast<std::uint32_t>(settings_.refresh_blocks_per_message);
        machine_work.invalidate_gp_caches = !first_frame_ && !settings_.refresh_caches;
    }
    if (classify) rebuild_pyramid(unscaled ? &*unscaled : nullptr, emptiness, emptiness_at, report);
    report.pyramid_cells_occupied = pyramid_.occupied_cells(0);
    // Depths are recorded only where the pyramid finds them: without skipping the buffer stays empty.
    report.depth_buffer_used = settings_.depth_buffer && settings_.pyramid_skipping && depth_for_ == frame.camera;
    if (!report.depth_buffer_used) std::fill(depth_.begin(), depth_.end(), 0);
    depth_for_ = frame.camera;
    // Each GP holds the whole pyramid of binary volumes, a bit a cell, beside its cache.
    machine_work.gp_resident_bits = settings_.pyramid_skipping ? pyramid_.total_cells() : 0;
    machine_work.phases.push_back(cast_frame(frame.camera, report));
    first_frame_ = false;
    report.caches_invalidated = machine_work.invalidate_gp_caches || machine_work.refresh_gp_caches;
    report.caches_refreshed = machine_work.refresh_gp_caches;
    report.final_image = report.passes.back().image;
    return report;
}

}  // namespace pp5
