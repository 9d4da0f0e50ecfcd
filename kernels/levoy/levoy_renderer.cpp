#include "kernels/levoy/levoy_renderer.h"

#include "kernels/levoy/geometry_programs.h"
#include "kernels/levoy/ray_caster.h"
#include "sim/core/input_error.h"

#include <algorithm>
#include <numeric>

namespace pp5 {

bool shading_depends_on_view(const PhongLighting& lighting) {
    return lighting.light_follows_camera || lighting.specular > 0.0f || lighting.depth_cue_k2 != 0.0f;
}

namespace {
int voxel_bits_of(const VoxelRecordLayout& layout) { return 3 * layout.color_bits + layout.opacity_bits; }
}  // namespace

LevoyRenderer::LevoyRenderer(Machine& machine, const Volume& volume, const LevoySettings& settings,
                             const LevoyImageSettings& image)
    : machine_(machine),
      settings_(settings),
      image_(image),
      dims_(volume.dims()),
      spacing_(volume.spacing()),
      pixel_processors_(machine, volume, settings),
      blocks_(pixel_processors_.placement(), settings.block_cells, voxel_bits_of(settings.layout)) {
    if (image.width < 1 || image.height < 1) throw InputError("scenario", "image.width", "the image needs at least one pixel");
    for (auto& gp : machine.gps()) gp->cache(blocks_.block_bits());  // InputError if one block does not fit
    depth_.assign(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height), 0);
}

Tick LevoyRenderer::distribute_pyramid(Tick start) {
    // Every renderer broadcasts one bit per voxel it holds, a slot at a time, once its PPs are free;
    // every GP takes every message in and, with all of them, builds the whole pyramid.
    RingNetwork& ring = machine_.ring();
    const VoxelPlacement& placement = pixel_processors_.placement();
    std::vector<std::pair<Tick, std::size_t>> ready;
    for (auto& r : machine_.renderers()) ready.emplace_back(std::max(start, r->busy_until()), r->index());
    std::sort(ready.begin(), ready.end());
    const std::uint64_t bits_per_slot = static_cast<std::uint64_t>(placement.shape().columns) * static_cast<std::uint64_t>(placement.shape().rows);
    // Each GP takes every message in as it arrives, after the one before (taking a message in is
    // slower than the ring delivers it), then builds.
    const GpCostModel& costs = machine_.gps().front()->costs();
    std::vector<RingTransit> transits;
    for (const auto& [at, r] : ready) {
        const std::size_t station = ring.position(StationKind::Renderer, r);
        for (int slot = 0; slot < placement.slots_used(static_cast<int>(r)); ++slot)
            transits.push_back(ring.transmit(at, RingMessage{MessageKind::Pyramid, station, 0, bits_per_slot, true}));
    }
    std::sort(transits.begin(), transits.end(), [](const RingTransit& a, const RingTransit& b) { return a.arrival < b.arrival; });
    Tick taken_in = start;
    Tick receiving = 0;
    for (const RingTransit& transit : transits) {
        const Tick receive = costs.message_receive + static_cast<Tick>(transit.words) * costs.receive_per_word;
        taken_in = std::max(taken_in, transit.arrival) + receive;
        receiving += receive;
    }
    const Tick build = static_cast<Tick>(pyramid_.total_cells()) * costs.pyramid_build_per_cell;
    for (auto& gp : machine_.gps()) {
        gp->busy_ps += static_cast<std::uint64_t>(receiving + build);
        if (TraceRecorder* trace = machine_.trace()) trace->slice(trace->track("GPs", gp->name()), "building the pyramid", taken_in, taken_in + build);
    }
    return taken_in + build;
}

void LevoyRenderer::set_polygons(const std::vector<PolygonSpec>& polygons) {
    polygons_.clear();
    for (const PolygonSpec& p : polygons) polygons_.push_back(prepare_polygon(p));
    polygons_changed_ = true;
}

GeometryReport LevoyRenderer::scan_convert(Tick start) {
    GeometryReport report;
    report.ran = true;
    report.start_ps = start;
    report.end_ps = start;
    const std::vector<glm::dvec3> offsets = subvoxel_offsets(settings_.jitter_samples);
    const PpProgramInputs inputs = pixel_processors_.program_inputs();
    const VoxelPlacement& placement = pixel_processors_.placement();
    RingNetwork& ring = machine_.ring();
    for (const PreparedPolygon& polygon : polygons_) {
        ++report.polygons;
        if (polygon.degenerate) continue;
        const PpProgram program = build_polygon_program(polygon, settings_.jitter_samples, dims_, inputs);
        // The host broadcasts the polygons one after another: D, E and F of every expression, a word
        // each; each renderer takes them in the order they arrive.
        const auto words = static_cast<std::uint64_t>(program.expressions) * 3;
        const RingTransit transit = ring.transmit(start, RingMessage{MessageKind::Command, 0, 0, words * 32, true});
        const PpProgramPass pass = pixel_processors_.run_over_slots(
            program, [&](const SlotFrame& frame) { return polygon_reaches_slot(polygon, frame, dims_, placement.shape()); },
            [&](const SlotFrame& frame) { return polygon_expressions(polygon, offsets, frame, settings_.layout); }, transit.arrival);
        for (const auto& r : machine_.renderers()) report.end_ps = std::max(report.end_ps, r->busy_until());
        report.slots += pass.slots;
    }
    machine_.events().run_until();
    return report;
}

RayCastJob LevoyRenderer::cast_frame(const Camera& camera, LevoyFrameReport& report) {
    const int width = image_.width;
    const int height = image_.height;
    const int tile = settings_.tile_pixels;
    const int tiles_x = (width + tile - 1) / tile;
    const int tiles_y = (height + tile - 1) / tile;
    const auto tile_of = [&](std::uint32_t p) {
        const int x = static_cast<int>(p % static_cast<std::uint32_t>(width));
        const int y = static_cast<int>(p / static_cast<std::uint32_t>(width));
        return (y / tile) * tiles_x + x / tile;
    };
    const auto pixels_in_tile = [&](int t) {
        const int x0 = (t % tiles_x) * tile;
        const int y0 = (t / tiles_x) * tile;
        return static_cast<std::uint32_t>((std::min(width, x0 + tile) - x0) * (std::min(height, y0 + tile) - y0));
    };

    RayCastSettings cast_settings;
    cast_settings.width = width;
    cast_settings.height = height;
    cast_settings.sample_step = image_.sample_step;
    cast_settings.early_termination = image_.termination_opacity < 1.0f;
    cast_settings.termination_opacity = image_.termination_opacity;
    cast_settings.background = image_.background;
    cast_settings.pyramid_skipping = settings_.pyramid_skipping;
    const RayCaster caster(shaded_, pyramid_, blocks_, camera, cast_settings);
    AdaptiveRefinement refinement(width, height, settings_.refinement);

    RayCastJob job;
    job.tiles = tiles_x * tiles_y;
    std::vector<std::uint32_t> cast_in_tile(static_cast<std::size_t>(job.tiles), 0);
    // The refinement decision's square tests, by the tile of each square's top-left corner.
    const auto tests_per_tile = [&] {
        std::vector<std::uint32_t> tests(static_cast<std::size_t>(job.tiles), 0);
        for (const std::uint32_t corner : refinement.tested_squares()) ++tests[static_cast<std::size_t>(tile_of(corner))];
        return tests;
    };
    std::vector<std::uint32_t> slot_of(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0);
    while (!refinement.finished()) {
        const int pass = refinement.passes_recorded();
        const std::vector<std::uint32_t>& pending = refinement.pending();
        // Rays grouped by tile, row by row within a tile: the order a GP casts them in (a counting
        // sort of the row-major pending list by tile keeps rows in order).
        std::vector<std::uint32_t> tile_start(static_cast<std::size_t>(job.tiles) + 1, 0);
        for (const std::uint32_t p : pending) ++tile_start[static_cast<std::size_t>(tile_of(p)) + 1];
        std::partial_sum(tile_start.begin(), tile_start.end(), tile_start.begin());
        std::vector<std::uint32_t> order(pending.size());
        {
            std::vector<std::uint32_t> next = tile_start;
            for (const std::uint32_t p : pending) order[next[static_cast<std::size_t>(tile_of(p))]++] = p;
        }
        CastBatch batch = caster.cast(order, settings_.depth_buffer ? std::span<const std::uint32_t>(depth_) : std::span<const std::uint32_t>());
        for (std::size_t i = 0; i < pending.size(); ++i) slot_of[pending[i]] = static_cast<std::uint32_t>(i);
        std::vector<glm::vec4> colors(pending.size());
        RefinementPassReport pass_report;
        for (std::size_t i = 0; i < order.size(); ++i) {
            colors[slot_of[order[i]]] = batch.colors[i];
            ++cast_in_tile[static_cast<std::size_t>(tile_of(order[i]))];
            const RayWork& ray = batch.rays[i];
            if (settings_.depth_buffer && settings_.pyramid_skipping) depth_[ray.pixel] = ray.first_sample;
            pass_report.samples += ray.samples;
        }
        pass_report.rays = order.size();

        const std::vector<std::uint32_t> tests = tests_per_tile();
        refinement.record(colors);
        pass_report.pixels_cast = refinement.pixels_cast();
        pass_report.image = refinement.image();
        report.passes.push_back(std::move(pass_report));

        for (int t = 0; t < job.tiles; ++t) {
            TileTask task;
            task.pass = pass;
            task.tile = t;
            task.first_ray = tile_start[static_cast<std::size_t>(t)];
            task.ray_count = tile_start[static_cast<std::size_t>(t) + 1] - task.first_ray;
            task.squares_tested = tests[static_cast<std::size_t>(t)];
            task.tile_pixels = pixels_in_tile(t);
            task.pixels_filled = task.tile_pixels - cast_in_tile[static_cast<std::size_t>(t)];
            if (task.ray_count > 0 || task.squares_tested > 0) job.tasks.push_back(task);
        }
        job.passes.push_back(std::move(batch));
    }
    // The last decision, that nothing more splits, was made too: charge its tests to the last pass.
    if (!job.passes.empty() && !refinement.tested_squares().empty()) {
        const std::vector<std::uint32_t> tests = tests_per_tile();
        for (int t = 0; t < job.tiles; ++t) {
            if (tests[static_cast<std::size_t>(t)] == 0) continue;
            TileTask task;
            task.pass = static_cast<int>(job.passes.size()) - 1;
            task.tile = t;
            task.squares_tested = tests[static_cast<std::size_t>(t)];
            task.tile_pixels = pixels_in_tile(t);
            job.tasks.push_back(task);
        }
    }
    return job;
}

LevoyFrameReport LevoyRenderer::render(const LevoyFrameInputs& frame) {
    LevoyFrameReport report;
    report.start_ps = machine_.events().now();

    // Shade only for a view the colours depend on; otherwise keep the view they were shaded for.
    ShadingView view = make_shading_view(frame.camera, dims_, spacing_);
    if (shaded_for_ && !shading_depends_on_view(frame.lighting)) view = *shaded_for_;
    // A moved region of interest needs fresh opacities (classification) but no new colours.
    const bool region_changed = frame.region != region_;
    bool classify = first_frame_ || frame.classification_changed || region_changed;
    bool reshade = first_frame_ || frame.classification_changed || frame.lighting_changed || shaded_for_ != view;
    if (!polygons_.empty() && (classify || reshade || polygons_changed_)) classify = reshade = true;  // matte into fresh voxels
    polygons_changed_ = false;
    report.pixel_processors = pixel_processors_.update(frame.classification, frame.colors, frame.lighting, view, classify, reshade);
    shaded_for_ = view;
    region_ = frame.region;
    Tick t = report.pixel_processors.end_ps;
    // The pyramid marks what the classification leaves non-empty before the region scales it: a
    // superset of what is non-empty after (so skipping stays exact), which a moving region does not
    // change even where its scaling rounds small opacities to zero.
    std::optional<ShadedVolume> unscaled;
    if (classify && region_) unscaled = pixel_processors_.shaded_volume();
    if (classify && region_) {
        const PpProgram program = build_region_program(*region_, dims_, pixel_processors_.program_inputs());
        const RegionOfInterest& region = *region_;
        report.region = pixel_processors_.run_over_slots(
            program, [](const SlotFrame&) { return true; }, [&](const SlotFrame& f) { return region_expressions(region, f); }, t);
        machine_.events().run_until();
        t = report.region.end_ps;
    }
    if (!polygons_.empty() && reshade) {
        report.geometry = scan_convert(t);
        t = report.geometry.end_ps;
    }

    if (classify || reshade) {
        shaded_ = pixel_processors_.shaded_volume();
        if (!first_frame_) {
            for (auto& gp : machine_.gps()) gp->cache(blocks_.block_bits()).invalidate();
            report.caches_invalidated = true;
        }
    }
    if (classify) {
        BinaryPyramid fresh = BinaryPyramid::from_opacity(shaded_, unscaled ? &*unscaled : nullptr);
        if (first_frame_ || !fresh.same_cells(pyramid_)) {
            pyramid_ = std::move(fresh);
            const Tick before = t;
            t = distribute_pyramid(t);
            report.pyramid_rebuilt = true;
            report.pyramid_ps = t - before;
            depth_for_.reset();
        }
    }
    report.pyramid_cells_occupied = pyramid_.occupied_cells(0);
    report.depth_buffer_used = settings_.depth_buffer && depth_for_ == frame.camera;
    if (!report.depth_buffer_used) std::fill(depth_.begin(), depth_.end(), 0);
    depth_for_ = frame.camera;

    const RayCastJob job = cast_frame(frame.camera, report);
    RayCastTimingOptions options;
    options.assignment = settings_.ray_assignment;
    report.ray_cast = time_ray_casting(machine_, blocks_, job, options, t);
    for (std::size_t p = 0; p < report.passes.size(); ++p) report.passes[p].end_ps = report.ray_cast.pass_end[p] - report.start_ps;
    report.end_ps = report.ray_cast.end;
    report.final_image = report.passes.back().image;
    first_frame_ = false;
    return report;
}

}  // namespace pp5
