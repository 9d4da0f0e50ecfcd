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

namespace {

// Every renderer broadcasts one bit per voxel it holds, a slot at a time, once its PPs are free; every
// GP takes every message in and, with all of them, builds the whole pyramid. Returns when it is built.
Tick distribute_pyramid(Machine& machine, const PyramidWork& work, Tick start) {
    RingNetwork& ring = machine.ring();
    std::vector<std::pair<Tick, std::size_t>> ready;
    for (auto& r : machine.renderers()) ready.emplace_back(std::max(start, r->busy_until()), r->index());
    std::sort(ready.begin(), ready.end());
    // Each GP takes every message in as it arrives, after the one before (taking a message in is
    // slower than the ring delivers it), then builds.
    const GpCostModel& costs = machine.gps().front()->costs();
    std::vector<RingTransit> transits;
    for (const auto& [at, r] : ready) {
        const std::size_t station = ring.position(StationKind::Renderer, r);
        for (int slot = 0; slot < work.slots_per_renderer[r]; ++slot)
            transits.push_back(ring.transmit(at, RingMessage{MessageKind::Pyramid, station, 0, work.bits_per_slot, true}));
    }
    std::sort(transits.begin(), transits.end(), [](const RingTransit& a, const RingTransit& b) { return a.arrival < b.arrival; });
    Tick taken_in = start;
    Tick receiving = 0;
    for (const RingTransit& transit : transits) {
        const Tick receive = costs.message_receive + static_cast<Tick>(transit.words) * costs.receive_per_word;
        taken_in = std::max(taken_in, transit.arrival) + receive;
        receiving += receive;
    }
    const Tick build = static_cast<Tick>(work.cells) * costs.pyramid_build_per_cell;
    for (auto& gp : machine.gps()) {
        gp->busy_ps += static_cast<std::uint64_t>(receiving + build);
        if (TraceRecorder* trace = machine.trace()) trace->slice(trace->track("GPs", gp->name()), "building the pyramid", taken_in, taken_in + build);
    }
    return taken_in + build;
}

// The host broadcasts the polygons one after another; each renderer runs them in the order they arrive.
GeometryReport time_scan_conversion(Machine& machine, const LevoyFrameWork& work, Tick start) {
    GeometryReport report;
    report.ran = true;
    report.polygons = work.polygons;
    report.start_ps = start;
    report.end_ps = start;
    for (const PolygonWork& polygon : work.polygon_passes) {
        const RingTransit transit = machine.ring().transmit(start, RingMessage{MessageKind::Command, 0, 0, polygon.command_bits, true});
        const PpProgramPass pass = PpShading::schedule(machine, polygon.pass, transit.arrival);
        for (const auto& r : machine.renderers()) report.end_ps = std::max(report.end_ps, r->busy_until());
        report.slots += pass.slots;
    }
    machine.events().run_until();
    return report;
}

}  // namespace

LevoyFrameTiming time_levoy_frame(Machine& machine, VoxelBlocks& blocks, const LevoyFrameWork& work) {
    LevoyFrameTiming timing;
    timing.start_ps = machine.events().now();
    timing.pixel_processors = PpShading::time(machine, work.pixel_processors, timing.start_ps);
    Tick t = timing.pixel_processors.end_ps;
    if (work.region) {
        timing.region = PpShading::schedule(machine, *work.region, t);
        machine.events().run_until();
        t = timing.region.end_ps;
    }
    if (work.scan_converted) {
        timing.geometry = time_scan_conversion(machine, work, t);
        t = timing.geometry.end_ps;
    }
    if (work.invalidate_caches) {
        for (auto& gp : machine.gps()) gp->cache(blocks.block_bits()).invalidate();
    }
    if (work.pyramid) {
        const Tick before = t;
        t = distribute_pyramid(machine, *work.pyramid, t);
        timing.pyramid_ps = t - before;
    }
    RayCastTimingOptions options;
    options.assignment = work.assignment;
    timing.ray_cast = time_ray_casting(machine, blocks, work.ray_cast, options, t);
    timing.end_ps = timing.ray_cast.end;
    return timing;
}

PyramidWork LevoyRenderer::pyramid_work() const {
    const VoxelPlacement& placement = pixel_processors_.placement();
    PyramidWork work;
    for (std::size_t r = 0; r < machine_.renderers().size(); ++r) work.slots_per_renderer.push_back(placement.slots_used(static_cast<int>(r)));
    work.bits_per_slot = static_cast<std::uint64_t>(placement.shape().columns) * static_cast<std::uint64_t>(placement.shape().rows);
    work.cells = pyramid_.total_cells();
    return work;
}

void LevoyRenderer::set_polygons(const std::vector<PolygonSpec>& polygons) {
    polygons_.clear();
    for (const PolygonSpec& p : polygons) polygons_.push_back(prepare_polygon(p));
    polygons_changed_ = true;
}

std::vector<PolygonWork> LevoyRenderer::scan_convert() {
    const std::vector<glm::dvec3> offsets = subvoxel_offsets(settings_.jitter_samples);
    const PpProgramInputs inputs = pixel_processors_.program_inputs();
    const VoxelPlacement& placement = pixel_processors_.placement();
    std::vector<PolygonWork> passes;
    for (const PreparedPolygon& polygon : polygons_) {
        if (polygon.degenerate) continue;
        PpProgram program = build_polygon_program(polygon, settings_.jitter_samples, dims_, inputs);
        // D, E and F of every expression, a word each.
        const auto bits = static_cast<std::uint64_t>(program.expressions) * 3 * 32;
        passes.push_back(PolygonWork{
            pixel_processors_.execute(
                program, [&](const SlotFrame& frame) { return polygon_reaches_slot(polygon, frame, dims_, placement.shape()); },
                [&](const SlotFrame& frame) { return polygon_expressions(polygon, offsets, frame, settings_.layout); }),
            bits, polygon.area, static_cast<int>(polygon.edge_normals.size())});
    }
    return passes;
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
    LevoyFrameWork& work = report.work;
    work.voxels = static_cast<std::uint64_t>(dims_.x) * static_cast<std::uint64_t>(dims_.y) * static_cast<std::uint64_t>(dims_.z);
    work.jitter_samples = settings_.jitter_samples;

    // Function first: what this frame changes, and the work that follows from it.
    // Shade only for a view the colours depend on; otherwise keep the view they were shaded for.
    ShadingView view = make_shading_view(frame.camera, dims_, spacing_);
    if (shaded_for_ && !shading_depends_on_view(frame.lighting)) view = *shaded_for_;
    // A moved region of interest needs fresh opacities (classification) but no new colours.
    const bool region_changed = frame.region != region_;
    bool classify = first_frame_ || frame.classification_changed || region_changed;
    bool reshade = first_frame_ || frame.classification_changed || frame.lighting_changed || shaded_for_ != view;
    if (!polygons_.empty() && (classify || reshade || polygons_changed_)) classify = reshade = true;  // matte into fresh voxels
    polygons_changed_ = false;
    work.pixel_processors = pixel_processors_.compute(frame.classification, frame.colors, frame.lighting, view, classify, reshade);
    shaded_for_ = view;
    region_ = frame.region;
    // The pyramid marks what the classification leaves non-empty before the region scales it: a
    // superset of what is non-empty after (so skipping stays exact), which a moving region does not
    // change even where its scaling rounds small opacities to zero.
    std::optional<ShadedVolume> unscaled;
    if (classify && region_) {
        unscaled = pixel_processors_.shaded_volume();
        const PpProgram program = build_region_program(*region_, dims_, pixel_processors_.program_inputs());
        const RegionOfInterest& region = *region_;
        work.region = pixel_processors_.execute(
            program, [](const SlotFrame&) { return true; }, [&](const SlotFrame& f) { return region_expressions(region, f); });
    }
    if (!polygons_.empty() && reshade) {
        work.scan_converted = true;
        work.polygons = polygons_.size();
        work.polygon_passes = scan_convert();
    }
    if (classify || reshade) {
        shaded_ = pixel_processors_.shaded_volume();
        work.invalidate_caches = !first_frame_;
    }
    if (classify) {
        BinaryPyramid fresh = BinaryPyramid::from_opacity(shaded_, unscaled ? &*unscaled : nullptr);
        if (first_frame_ || !fresh.same_cells(pyramid_)) {
            pyramid_ = std::move(fresh);
            work.pyramid = pyramid_work();
            depth_for_.reset();
        }
    }
    report.pyramid_cells_occupied = pyramid_.occupied_cells(0);
    report.depth_buffer_used = settings_.depth_buffer && depth_for_ == frame.camera;
    if (!report.depth_buffer_used) std::fill(depth_.begin(), depth_.end(), 0);
    depth_for_ = frame.camera;
    work.ray_cast = cast_frame(frame.camera, report);
    work.assignment = settings_.ray_assignment;
    first_frame_ = false;

    // Then time it on this machine.
    const LevoyFrameTiming timing = time_levoy_frame(machine_, blocks_, work);
    report.start_ps = timing.start_ps;
    report.end_ps = timing.end_ps;
    report.pixel_processors = timing.pixel_processors;
    report.region = timing.region;
    report.geometry = timing.geometry;
    report.pyramid_rebuilt = work.pyramid.has_value();
    report.pyramid_ps = timing.pyramid_ps;
    report.caches_invalidated = work.invalidate_caches;
    report.ray_cast = timing.ray_cast;
    for (std::size_t p = 0; p < report.passes.size(); ++p) report.passes[p].end_ps = report.ray_cast.pass_end[p] - report.start_ps;
    report.final_image = report.passes.back().image;
    return report;
}

}  // namespace pp5
