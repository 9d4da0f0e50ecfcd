// The GPs' ray casting: the pyramid of binary volumes, adaptive refinement, the ray caster's image
// against the reference compositor (exact, with and without skipping), its work records, and the
// whole frame on a small machine (caches warm across frames, identical results at 1 and 2 threads).

#include "kernels/levoy/ray_caster.h"
#include "kernels/levoy/adaptive_refinement.h"
#include "kernels/levoy/binary_pyramid.h"
#include "kernels/levoy/levoy_costs.h"
#include "kernels/levoy/levoy_renderer.h"
#include "kernels/levoy/ray_cast_work.h"
#include "kernels/levoy/tests/levoy_test_support.h"
#include "scene/reference/composite.h"
#include "scene/reference/trilinear.h"
#include "scene/volume/phantoms.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"
#include "tests/unit/render/test_scenes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numeric>
#include <random>

namespace pp5 {
namespace {

MachineConfig ray_casting_machine(std::initializer_list<std::string_view> overrides = {}) {
    return test::levoy_config({"renderer.count=4", "renderer.pp_columns=32", "renderer.pp_rows=32",
                               "renderer.backing_store_bits=2048", "gp.count=4", "levoy.tile_pixels=8"},
                              overrides);
}

// 8-bit codes, all transparent.
ShadedCodes empty_volume(glm::ivec3 dims) { return ShadedCodes(dims, glm::vec3(1.0f), glm::vec4(255.0f)); }

TEST(ShadedCodes, InterpolateExactlyAsTheirDecodedFloatsAtEightAndSixteenBits) {
    const glm::ivec3 dims(7, 6, 5);
    for (const float code_max : {255.0f, 4095.0f}) {
        ShadedCodes codes(dims, glm::vec3(1.0f), glm::vec4(code_max, code_max, code_max, 255.0f));
        EXPECT_EQ(codes.narrow(), code_max <= 255.0f);
        std::mt19937 random(11);
        std::uniform_int_distribution<int> colour(0, static_cast<int>(code_max));
        std::uniform_int_distribution<int> opacity(0, 255);
        for (std::size_t i = 0; i < codes.size(); ++i)
            codes.set(i, glm::u16vec4(colour(random), colour(random), colour(random), opacity(random)));
        const ShadedVolume floats = codes.decoded();
        const detail::Grid grid(dims);
        std::uniform_real_distribution<float> along(-0.5f, 7.5f);
        for (int n = 0; n < 500; ++n) {
            const detail::Cell cell = grid.cell({along(random), along(random), along(random)});
            const glm::vec4 from_codes = codes.narrow()
                                             ? grid.interpolate_codes(cell, codes.narrow_codes(), codes.code_max())
                                             : grid.interpolate_codes(cell, codes.wide_codes(), codes.code_max());
            ASSERT_EQ(from_codes, grid.interpolate_rgba(cell, floats.rgba.data()))
                << "sample " << n << ", largest code " << code_max;
        }
    }
}

TEST(BinaryPyramid, ACellIsOccupiedWhenAnyOfItsCornersIsOpaque) {
    ShadedCodes v = empty_volume({9, 9, 9});
    v.set(static_cast<std::size_t>(4 + 9 * (4 + 9 * 4)), {0, 0, 0, 128});  // voxel (4,4,4)
    const BinaryPyramid p = BinaryPyramid::from_opacity(v);
    EXPECT_EQ(p.cell_dims(0), glm::ivec3(8));
    EXPECT_EQ(p.occupied_cells(0), 8u);  // the eight cells around the voxel
    EXPECT_TRUE(p.occupied(0, {3, 3, 3}));
    EXPECT_TRUE(p.occupied(0, {4, 4, 4}));
    EXPECT_FALSE(p.occupied(0, {5, 4, 4}));
    // Cells 3 and 4 fall in different halves at every level up to 8 cells: each level holds 8 again,
    // until the top single cell.
    ASSERT_EQ(p.levels(), 4);
    EXPECT_EQ(p.occupied_cells(1), 8u);
    EXPECT_EQ(p.occupied_cells(2), 8u);
    EXPECT_EQ(p.cell_dims(3), glm::ivec3(1));
    EXPECT_TRUE(p.occupied(3, {0, 0, 0}));
    EXPECT_EQ(p.total_cells(), 512u + 64u + 8u + 1u);
}

TEST(BinaryPyramid, SameCellsComparesTheNonEmptySet) {
    ShadedCodes a = empty_volume({6, 5, 4});
    a.set(7, {0, 0, 0, 51});
    ShadedCodes b = a;
    b.set(7, {0, 0, 0, 230});  // other opacity, same set
    ShadedCodes c = a;
    c.set(8, {0, 0, 0, 1});  // one more non-empty voxel
    EXPECT_TRUE(BinaryPyramid::from_opacity(a).same_cells(BinaryPyramid::from_opacity(b)));
    EXPECT_FALSE(BinaryPyramid::from_opacity(a).same_cells(BinaryPyramid::from_opacity(c)));
}

TEST(BinaryPyramid, EmptyLevelsAboveACellAreTheLevelsAClimbFromItPassesThrough) {
    // Sparse random opacity in volumes of uneven sizes: for every empty cell of level 0, the count of
    // empty levels from level 1 up equals a climb that tests one level at a time.
    std::mt19937 random(5);
    for (const glm::ivec3 dims : {glm::ivec3(4, 3, 3), glm::ivec3(23, 17, 30), glm::ivec3(40, 9, 66)}) {
        ShadedCodes v = empty_volume(dims);
        std::uniform_int_distribution<std::size_t> voxel(0, v.size() - 1);
        v.set(0, {0, 0, 0, 200});
        for (std::size_t n = 0; n < v.size() / 1000; ++n) v.set(voxel(random), {0, 0, 0, 200});
        const BinaryPyramid p = BinaryPyramid::from_opacity(v);
        ASSERT_GE(p.levels(), 2);
        const glm::ivec3 cells = p.cell_dims(0);
        int checked = 0;
        for (int z = 0; z < cells.z; ++z)
            for (int y = 0; y < cells.y; ++y)
                for (int x = 0; x < cells.x; ++x) {
                    const glm::ivec3 c(x, y, z);
                    if (p.occupied(0, c)) continue;
                    int climbed = 0;
                    while (climbed + 1 < p.levels() && !p.occupied(climbed + 1, c >> (climbed + 1))) ++climbed;
                    ASSERT_EQ(p.empty_levels_above(c), climbed) << "cell " << x << "," << y << "," << z;
                    ++checked;
                }
        EXPECT_GT(checked, 0);
    }
}

TEST(OrderByTile, GroupsThePendingPixelsByTileKeepingEachTilesRowsInOrder) {
    const ScreenTiles tiles(37, 21, 8);  // uneven tiles at the right and bottom edges
    std::mt19937 random(3);
    std::bernoulli_distribution chosen(0.4);
    std::vector<std::uint32_t> pending;
    for (std::uint32_t p = 0; p < 37u * 21u; ++p)
        if (chosen(random)) pending.push_back(p);
    const TileOrder order = order_by_tile(tiles, pending);
    std::vector<std::uint32_t> expected = pending;
    std::stable_sort(expected.begin(), expected.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return tiles.of(a) < tiles.of(b); });
    EXPECT_EQ(order.pixels, expected);
    ASSERT_EQ(order.first.size(), static_cast<std::size_t>(tiles.count()) + 1);
    for (int t = 0; t < tiles.count(); ++t)
        for (std::uint32_t i = order.first[static_cast<std::size_t>(t)];
             i < order.first[static_cast<std::size_t>(t) + 1]; ++i)
            ASSERT_EQ(tiles.of(order.pixels[i]), t);
    std::swap(pending[0], pending[1]);
    EXPECT_THROW(order_by_tile(tiles, pending), std::invalid_argument);
}

TEST(RayWorkRecorder, APassRecordsATaskPerTileAnItemPerRayAndAStepPerLookUp) {
    // Two tiles of 2x1 pixels; tile 0 casts two rays, tile 1 none but has a refinement test.
    const ScreenTiles tiles(4, 1, 2);
    CastBatch batch;
    batch.touches = {{7, 2, 3}, {8, 1, 0}};
    RayWork looks_up;  // two look-ups, then 4 samples and 5 pyramid steps
    looks_up.first_touch = 0;
    looks_up.touch_count = 2;
    looks_up.tail_samples = 4;
    looks_up.tail_pyramid_steps = 5;
    looks_up.samples = 7;
    looks_up.pyramid_steps = 8;
    looks_up.terminated = true;
    RayWork misses;  // never meets a block: its setup alone
    batch.rays = {looks_up, misses};
    TileOrder order;
    order.first = {0, 2, 2};
    order.pixels = {0, 1};
    GpPhase job;
    RayCastCounts counts;
    RayWorkRecorder recorder(tiles, false, job, counts);
    const std::vector<std::uint32_t> tests = {0, 3}, filled = {1, 0};
    EXPECT_EQ(recorder.add_pass(2, batch, order, tests, filled), 7u);

    const auto ops = [&](std::uint32_t first, std::uint32_t count) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
        for (std::uint32_t i = first; i < first + count; ++i) out.emplace_back(job.ops[i].kind, job.ops[i].count);
        return out;
    };
    using Ops = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
    ASSERT_EQ(job.items.size(), 2u);
    ASSERT_EQ(job.steps.size(), 4u);
    ASSERT_EQ(job.tasks.size(), 2u);
    EXPECT_EQ(job.items[0].first_step, 0u);
    EXPECT_EQ(job.items[0].step_count, 3u);
    EXPECT_EQ(job.items[1].first_step, 3u);
    EXPECT_EQ(job.items[1].step_count, 1u);
    EXPECT_EQ(job.steps[0].block, 7u);
    EXPECT_EQ(ops(job.steps[0].first_op, job.steps[0].op_count),
              (Ops{{kRaySetup, 1}, {kSample, 2}, {kPyramidStep, 3}}));
    EXPECT_EQ(job.steps[1].block, 8u);
    EXPECT_EQ(ops(job.steps[1].first_op, job.steps[1].op_count), (Ops{{kSample, 1}}));
    EXPECT_EQ(job.steps[2].block, kNoFetch);
    EXPECT_EQ(ops(job.steps[2].first_op, job.steps[2].op_count), (Ops{{kSample, 4}, {kPyramidStep, 5}}));
    EXPECT_EQ(job.steps[3].block, kNoFetch);
    EXPECT_EQ(ops(job.steps[3].first_op, job.steps[3].op_count), (Ops{{kRaySetup, 1}}));

    const GpTask& cast = job.tasks[0];
    EXPECT_EQ(cast.group, 2u);
    EXPECT_EQ(cast.key, 0u);
    EXPECT_EQ(cast.first_item, 0u);
    EXPECT_EQ(cast.item_count, 2u);
    EXPECT_EQ(cast.op_count, 0u);
    EXPECT_EQ(ops(cast.first_finish_op, cast.finish_op_count), (Ops{{kPixelFill, 1}}));
    EXPECT_EQ(cast.pixels, 2u);
    const GpTask& tests_only = job.tasks[1];
    EXPECT_EQ(tests_only.key, 1u);
    EXPECT_EQ(tests_only.item_count, 0u);
    EXPECT_EQ(ops(tests_only.first_op, tests_only.op_count), (Ops{{kRefinementTest, 3}}));
    EXPECT_EQ(tests_only.finish_op_count, 0u);
    EXPECT_EQ(tests_only.pixels, 0u);
    // The operations are laid out tile by tile: the rays', then the task's own.
    EXPECT_EQ(job.ops.size(), 9u);
    EXPECT_EQ(cast.first_finish_op, 7u);
    EXPECT_EQ(tests_only.first_op, 8u);

    EXPECT_EQ(counts.rays, 2u);
    EXPECT_EQ(counts.samples, 7u);
    EXPECT_EQ(counts.pyramid_steps, 8u);
    EXPECT_EQ(counts.rays_terminated, 1u);
    EXPECT_EQ(counts.pixels_filled, 1u);
}

TEST(AdaptiveRefinement, NegativeThresholdCastsEveryPixelOnce) {
    AdaptiveRefinement r(37, 21, RefinementSettings{8, -1.0f});
    std::vector<int> times(37 * 21, 0);
    int passes = 0;
    while (!r.finished()) {
        for (const std::uint32_t p : r.pending()) ++times[p];
        r.record(std::vector<glm::vec4>(r.pending().size(), glm::vec4(0.5f)));
        ++passes;
    }
    EXPECT_TRUE(std::all_of(times.begin(), times.end(), [](int n) { return n == 1; }));
    EXPECT_EQ(r.pixels_cast(), 37u * 21u);
    EXPECT_GE(passes, 4);  // spacing 8, 4, 2, 1 and the uneven edge squares
}

TEST(AdaptiveRefinement, SmoothImageStopsAfterTheSparsePassAndInterpolatesExactly) {
    // Colours linear in x and y: no square's corners differ by more than the threshold, and bilinear
    // fill reproduces the plane everywhere.
    const int w = 33;
    const int h = 17;
    const auto plane = [](std::uint32_t p) {
        const float x = static_cast<float>(p % 33);
        const float y = static_cast<float>(p / 33);
        return glm::vec4(0.01f * x, 0.02f * y, 0.1f, 1.0f);
    };
    AdaptiveRefinement r(w, h, RefinementSettings{8, 0.2f});
    std::vector<glm::vec4> colors;
    for (const std::uint32_t p : r.pending()) colors.push_back(plane(p));
    EXPECT_EQ(r.pending().size(), 5u * 3u);  // x: 0 8 16 24 32, y: 0 8 16
    r.record(colors);
    EXPECT_TRUE(r.finished());
    EXPECT_EQ(r.tested_squares().size(), 4u * 2u);
    const Image image = r.image();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec4 expect = plane(static_cast<std::uint32_t>(x + w * y));
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(image.at(x, y)[c], expect[c], 1e-5f) << x << "," << y;
        }
}

TEST(AdaptiveRefinement, SplitsOnlyWhereCornersDiffer) {
    AdaptiveRefinement r(17, 17, RefinementSettings{8, 0.1f});
    std::vector<glm::vec4> colors;
    for (const std::uint32_t p : r.pending())
        colors.push_back(p == 16 ? glm::vec4(1.0f) : glm::vec4(0.0f));  // pixel (16, 0)
    r.record(colors);
    // Only the top-right square [8,16]x[0,8] touches the bright corner: its 5 new corners.
    EXPECT_EQ(r.pending().size(), 5u);
    for (const std::uint32_t p : r.pending()) {
        EXPECT_GE(p % 17, 8u);
        EXPECT_LE(p / 17, 8u);
    }
}

// A small shaded phantom with its pyramid and blocks, for casting.
struct Scene {
    Volume volume = make_head_phantom(32);
    MachineConfig config = ray_casting_machine();
    Machine machine{config};
    LevoyImageSettings image{72, 64, 1.0f, 1.0f, glm::vec3(0.1f, 0.1f, 0.2f)};
    Camera camera;
    LevoyFrameInputs inputs;

    Scene() {
        camera.projection = Projection::Perspective;
        const glm::vec3 center = test::box_center(volume);
        camera.eye = center + glm::vec3(-70.0f, -90.0f, 40.0f);
        camera.target = center;
        camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
        camera.fov_y_degrees = 40.0f;
        inputs.camera = camera;
        inputs.classification.kind = ClassificationKind::IsovalueContours;
        inputs.classification.contours = {{40.0f, 0.3f, 1.5f}, {160.0f, 0.9f, 1.5f}};
        inputs.colors = ColorMap{{{0.0f, {0.9f, 0.7f, 0.6f}}, {220.0f, {1.0f, 1.0f, 0.95f}}}};
    }
    CompositeSettings composite_settings() const {
        CompositeSettings s;
        s.width = image.width;
        s.height = image.height;
        s.sample_step = image.sample_step;
        s.early_termination = false;
        s.background = image.background;
        return s;
    }
};

TEST(RayCaster, FullyRefinedImageEqualsTheReferenceCompositorWithAndWithoutSkipping) {
    for (const bool skipping : {true, false}) {
        Scene s;
        s.config.apply_override("levoy.refinement_threshold=-1");
        s.config.apply_override(skipping ? "levoy.pyramid_skipping=true" : "levoy.pyramid_skipping=false");
        Machine machine(s.config);
        LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
        const LevoyFrameReport report = renderer.render(s.inputs);
        const Image reference = composite(renderer.shaded_volume(), s.camera, s.composite_settings());
        ASSERT_EQ(report.final_image.pixels.size(), reference.pixels.size());
        float worst = 0.0f;
        for (std::size_t i = 0; i < reference.pixels.size(); ++i)
            for (int c = 0; c < 4; ++c)
                worst = std::max(worst, std::abs(report.final_image.pixels[i][c] - reference.pixels[i][c]));
        EXPECT_LE(worst, 1.0f / 255.0f) << "skipping " << skipping;
        EXPECT_EQ(report.ray_cast.rays, static_cast<std::uint64_t>(s.image.width * s.image.height));
        if (skipping) {
            EXPECT_GT(report.ray_cast.samples_skipped, report.ray_cast.samples)
                << "the pyramid should pass over most samples";
            EXPECT_GT(report.ray_cast.pyramid_steps, 0u);
        } else {
            EXPECT_EQ(report.ray_cast.pyramid_steps, 0u);
        }
    }
}

TEST(LevoyRenderer, AGpMemoryTooSmallForThePyramidIsRefusedBeforeThePpsAreLoaded) {
    const Scene s;
    const std::uint64_t pyramid_cells = BinaryPyramid::total_cells_of(s.volume.dims());
    const std::uint64_t cache_bytes = Machine(s.config).gps().front()->cache_bits() / 8;
    const std::uint64_t needed = cache_bytes + (pyramid_cells + 7) / 8;
    {
        MachineConfig roomy = s.config;
        roomy.apply_override("gp.memory_bytes=" + std::to_string(needed));
        Machine machine(roomy);
        LevoyRenderer renderer(machine, s.volume, LevoySettings::from(roomy), s.image);
        renderer.render(s.inputs);
        EXPECT_EQ(renderer.pyramid().total_cells(), pyramid_cells);  // the up-front size is the built one's
    }
    MachineConfig tight = s.config;
    tight.apply_override("gp.memory_bytes=" + std::to_string(needed - 1));
    Machine machine(tight);
    try {
        LevoyRenderer renderer(machine, s.volume, LevoySettings::from(tight), s.image);
        FAIL() << "a GP one byte short of its cache and pyramid was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "gp.memory_bytes");
    }
    for (const auto& renderer : machine.renderers())
        EXPECT_EQ(renderer->backing_store_bits_used(), 0u) << "the PPs were loaded first";
}

TEST(RayCaster, SkippingChangesTheWorkNotThePixels) {
    Scene s;
    const ShadedCodes& shaded = [&]() -> const ShadedCodes& {
        static Machine machine(s.config);
        static LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
        renderer.render(s.inputs);
        return renderer.shaded_codes();
    }();
    const BinaryPyramid pyramid = BinaryPyramid::from_opacity(shaded);
    Machine machine(s.config);
    const VoxelPlacement placement(PlacementPolicy::Bricks, shaded.dims(), PpArrayShape{4, 32, 32, 2048}, 64);
    const VoxelBlocks blocks(placement, 4, 32);
    RayCastSettings settings;
    settings.width = s.image.width;
    settings.height = s.image.height;
    settings.early_termination = true;
    std::vector<std::uint32_t> pixels(static_cast<std::size_t>(settings.width * settings.height));
    std::iota(pixels.begin(), pixels.end(), 0u);
    settings.pyramid_skipping = true;
    const CastBatch skip = RayCaster(shaded, pyramid, blocks, s.camera, settings).cast(pixels);
    settings.pyramid_skipping = false;
    const CastBatch plain = RayCaster(shaded, pyramid, blocks, s.camera, settings).cast(pixels);
    std::uint64_t touched_skip = 0;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        ASSERT_EQ(skip.colors[i], plain.colors[i]) << "pixel " << i;
        // The samples that matter are the same ones; skipping only drops empty ones.
        EXPECT_LE(skip.rays[i].samples, plain.rays[i].samples);
        EXPECT_EQ(skip.rays[i].terminated, plain.rays[i].terminated);
        touched_skip += skip.rays[i].touch_count;
        // Every look-up's samples add up to the ray's.
        std::uint64_t counted = skip.rays[i].tail_samples;
        for (std::uint32_t t = 0; t < skip.rays[i].touch_count; ++t)
            counted += skip.touches[skip.rays[i].first_touch + t].samples;
        EXPECT_EQ(counted, skip.rays[i].samples);
    }
    EXPECT_GT(touched_skip, 0u);
    EXPECT_LT(skip.touches.size(), plain.touches.size());
}

TEST(LevoyRenderer, CachesStayWarmWhileVoxelsStayAndAreDroppedWhenTheyChange) {
    Scene s;
    s.inputs.lighting.light_follows_camera = false;  // view-independent shading: an orbit does not reshade
    s.inputs.lighting.specular = 0.0f;
    s.inputs.lighting.light_direction = glm::vec3(0.3f, -1.0f, 0.5f);
    Machine machine(s.config);
    LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
    const LevoyFrameReport first = renderer.render(s.inputs);
    EXPECT_TRUE(first.pyramid_rebuilt);
    EXPECT_GT(first.ray_cast.cache_misses, 0u);

    LevoyFrameInputs still = s.inputs;
    still.classification_changed = false;
    still.lighting_changed = false;
    const LevoyFrameReport again = renderer.render(still);
    EXPECT_FALSE(again.pixel_processors.shading.ran);
    EXPECT_FALSE(again.caches_invalidated);
    EXPECT_TRUE(again.depth_buffer_used);
    EXPECT_EQ(again.ray_cast.cache_misses, 0u) << "every block is still in a cache";
    EXPECT_LT(again.duration_ps(), first.duration_ps());
    EXPECT_EQ(again.final_image.pixels, first.final_image.pixels);

    LevoyFrameInputs lit = still;
    lit.lighting.light_direction = glm::vec3(-1.0f, 0.2f, 0.1f);
    lit.lighting_changed = true;
    const LevoyFrameReport relit = renderer.render(lit);
    EXPECT_TRUE(relit.pixel_processors.shading.ran);
    EXPECT_FALSE(relit.pixel_processors.classification.ran);
    EXPECT_TRUE(relit.caches_invalidated);
    EXPECT_FALSE(relit.pyramid_rebuilt);
    EXPECT_TRUE(relit.depth_buffer_used);
    EXPECT_GT(relit.ray_cast.cache_misses, 0u);

    LevoyFrameInputs hidden = lit;
    hidden.lighting_changed = false;
    hidden.classification_changed = true;
    hidden.classification.contours = {{160.0f, 0.9f, 1.5f}};
    const LevoyFrameReport rebuilt = renderer.render(hidden);
    EXPECT_TRUE(rebuilt.pyramid_rebuilt);
    EXPECT_GT(rebuilt.pyramid_ps, 0);
    EXPECT_FALSE(rebuilt.depth_buffer_used);
}

// The depth buffer records where the pyramid's skipping finds the first non-empty sample; without
// skipping it has nothing to start rays from, so the frame says it was not used.
TEST(LevoyRenderer, TheDepthBufferIsReportedOffWithoutPyramidSkipping) {
    Scene s;
    s.inputs.lighting.light_follows_camera = false;
    s.inputs.lighting.specular = 0.0f;
    s.config.set("levoy.pyramid_skipping", false, "test");
    Machine machine(s.config);
    LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
    const LevoyFrameReport first = renderer.render(s.inputs);
    LevoyFrameInputs still = s.inputs;
    still.classification_changed = false;
    still.lighting_changed = false;
    const LevoyFrameReport again = renderer.render(still);
    EXPECT_FALSE(again.depth_buffer_used);
    EXPECT_EQ(again.final_image.pixels, first.final_image.pixels);
}

// levoy.after_reshade = refresh: on a light change with the observer still, each GP asks again, a few
// blocks a message, for the blocks it used in the frame before, so it sends fewer fetch requests than
// when it drops them, and the picture is the same. (Against an observer move on Levoy's MR head
// sequence: Cli.OnTheMrHeadSequenceALightChangeThatRefreshesSendsFewerFetchesThanAnOrbit.)
TEST(LevoyRenderer, ALightChangeThatRefreshesTheCachesSendsFewerFetchesThanOneThatDropsThem) {
    const auto sequence = [](const char* after_reshade) {
        Scene s;
        s.config.set("levoy.after_reshade", std::string(after_reshade), "test");
        s.inputs.lighting.light_follows_camera = false;
        s.inputs.lighting.specular = 0.0f;
        s.inputs.lighting.light_direction = glm::vec3(0.3f, -1.0f, 0.5f);
        Machine machine(s.config);
        LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
        std::vector<LevoyFrameReport> frames;
        frames.push_back(renderer.render(s.inputs));
        LevoyFrameInputs moved = s.inputs;
        moved.camera.eye += glm::vec3(12.0f, -4.0f, 0.0f);
        moved.classification_changed = false;
        moved.lighting_changed = false;
        frames.push_back(renderer.render(moved));
        LevoyFrameInputs lit = moved;
        lit.lighting.light_direction = glm::vec3(-1.0f, 0.2f, 0.1f);
        lit.lighting_changed = true;
        frames.push_back(renderer.render(lit));
        return frames;
    };
    const std::vector<LevoyFrameReport> refreshed = sequence("refresh");
    const std::vector<LevoyFrameReport> dropped = sequence("drop");
    const LevoyFrameReport& orbit = refreshed[1];
    const LevoyFrameReport& light = refreshed[2];
    EXPECT_TRUE(light.caches_refreshed);
    EXPECT_FALSE(dropped[2].caches_refreshed);
    EXPECT_TRUE(dropped[2].caches_invalidated);
    EXPECT_GT(orbit.ray_cast.fetch_requests, 0u);
    // The blocks the orbit frame used are the ones asked for again.
    EXPECT_GT(light.ray_cast.blocks_refreshed, 0u);
    EXPECT_LE(light.ray_cast.blocks_refreshed, orbit.ray_cast.cache_hits + orbit.ray_cast.cache_misses);
    EXPECT_LT(light.ray_cast.fetch_requests, dropped[2].ray_cast.fetch_requests);
    // Refreshing or dropping changes when voxels arrive, never what is drawn.
    EXPECT_EQ(light.final_image.pixels, dropped[2].final_image.pixels);
    EXPECT_EQ(dropped[2].ray_cast.blocks_refreshed, 0u);
}

// Levoy's stationary lights: with their sum kept in each voxel's record, a frame that moves only the
// key light skips the stationary pass and shades in fewer PP cycles, a capping region's move stores the
// sum afresh (its gradients changed), so does the lights' return after the region moved while they were
// off, and every frame's picture is the one recomputing every light gives.
TEST(LevoyRenderer, StationaryLightsKeptInTheRecordGiveTheSameFramesAndCheaperLightMoves) {
    struct Run {
        std::vector<LevoyFrameReport> frames;
        int record_bits = 0;
    };
    const auto sequence = [](const char* bits) {
        Scene s;
        s.config.apply_override(std::string("levoy.stationary_light_bits=") + bits);
        s.inputs.lighting.light_follows_camera = false;
        s.inputs.lighting.specular = 0.0f;  // view-independent: an orbit reshades nothing
        s.inputs.lighting.light_direction = glm::vec3(0.3f, -1.0f, 0.5f);
        s.inputs.lighting.stationary_lights = {{glm::vec3(-1.0f, 0.4f, 0.6f), 0.5f},
                                               {glm::vec3(0.2f, 0.3f, 1.0f), 0.7f}};
        Scenario scenario;
        scenario.frames.push_back(FrameSpec{});
        scenario.frames.back().lighting = s.inputs.lighting;
        Machine machine(s.config);
        LevoyRenderer renderer(machine, s.volume, LevoySettings::for_scenario(s.config, scenario), s.image);
        Run run;
        run.record_bits = renderer.pixel_processors().placement().record_bits();
        LevoyFrameInputs frame = s.inputs;
        run.frames.push_back(renderer.render(frame));
        frame.classification_changed = false;
        frame.lighting.light_direction = glm::vec3(-1.0f, 0.2f, 0.1f);  // the key light moves
        run.frames.push_back(renderer.render(frame));
        frame.lighting_changed = false;
        frame.camera.eye += glm::vec3(12.0f, -4.0f, 0.0f);  // an orbit
        run.frames.push_back(renderer.render(frame));
        RegionOfInterest cut;
        cut.center = glm::vec3(16.0f);
        cut.half_size = glm::vec3(6.0f);
        cut.scale_inside = 0.02f;
        cut.transition = 3.0f;
        cut.cap = true;
        frame.region = cut;  // a capping region: its band's gradients change
        run.frames.push_back(renderer.render(frame));
        frame.lighting.light_direction = glm::vec3(0.5f, 0.5f, 0.7f);
        frame.lighting_changed = true;
        run.frames.push_back(renderer.render(frame));
        frame.lighting_changed = false;
        frame.region->center.x += 3.0f;  // the capping region moves: its band's gradients with it
        run.frames.push_back(renderer.render(frame));
        const auto stationary = frame.lighting.stationary_lights;
        frame.lighting.stationary_lights.clear();  // the stationary lights go off while the region moves
        frame.lighting_changed = true;
        frame.region->center.y -= 3.0f;
        run.frames.push_back(renderer.render(frame));
        frame.lighting.stationary_lights = stationary;  // and come back with the region where it is now
        run.frames.push_back(renderer.render(frame));
        return run;
    };
    const Run kept = sequence("10");
    const Run recomputed = sequence("0");
    EXPECT_EQ(kept.record_bits, recomputed.record_bits + 10);
    const std::vector<bool> stationary_ran = {true, false, false, true, false, true, false, true};
    ASSERT_EQ(kept.frames.size(), stationary_ran.size());
    for (std::size_t i = 0; i < kept.frames.size(); ++i) {
        EXPECT_EQ(kept.frames[i].pixel_processors.stationary_lights.ran, stationary_ran[i]) << "frame " << i;
        EXPECT_FALSE(recomputed.frames[i].pixel_processors.stationary_lights.ran) << "frame " << i;
        EXPECT_EQ(kept.frames[i].final_image.pixels, recomputed.frames[i].final_image.pixels) << "frame " << i;
    }
    for (const std::size_t light_move : {1u, 4u}) {
        const PpProgramPass& fast = kept.frames[light_move].pixel_processors.shading;
        const PpProgramPass& slow = recomputed.frames[light_move].pixel_processors.shading;
        ASSERT_TRUE(fast.ran && slow.ran);
        EXPECT_LT(fast.slot_cost.compute_cycles(), slow.slot_cost.compute_cycles()) << "frame " << light_move;
        EXPECT_LT(kept.frames[light_move].pixel_processors.duration_ps(),
                  recomputed.frames[light_move].pixel_processors.duration_ps());
    }
    EXPECT_FALSE(kept.frames[2].pixel_processors.shading.ran);
    // A lone processor shades a voxel once per light it computes: all three lights in the first frame
    // either way, then the key light alone when the stationary ones are kept.
    const auto voxel_shadings = [](const LevoyFrameReport& f) {
        std::uint64_t n = 0;
        for (const Phase& phase : f.work.machine.phases)
            if (const auto* pp = std::get_if<PpPhase>(&phase.work))
                for (const PpPhase::Pass& pass : pp->passes)
                    for (const GpOp& op : pass.on_one_processor) n += op.kind == kVoxelShading ? op.count : 0;
        return n;
    };
    const std::uint64_t voxels = 32 * 32 * 32;
    EXPECT_EQ(voxel_shadings(kept.frames[0]), 3 * voxels);
    EXPECT_EQ(voxel_shadings(recomputed.frames[0]), 3 * voxels);
    EXPECT_EQ(voxel_shadings(kept.frames[1]), voxels);
    EXPECT_EQ(voxel_shadings(recomputed.frames[1]), 3 * voxels);
}

// The field is refused by name when it alone keeps the volume from fitting the backing stores.
TEST(LevoyRenderer, AStationaryLightFieldThatCannotFitIsRefusedByName) {
    const MachineConfig config = ray_casting_machine();
    const Machine machine(config);
    const glm::ivec3 dims(64, 64, 30);  // 30 slots a PP: 1920 of the 2048 bits at 64 bits a record
    LevoySettings settings = LevoySettings::from(config);
    EXPECT_NO_THROW(LevoyRenderer::check_fits(machine, dims, settings));
    settings.store.layout.stationary_light_bits = 10;
    try {
        LevoyRenderer::check_fits(machine, dims, settings);
        FAIL() << "74-bit records of 30 slots need 2220 bits of 2048";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "levoy.stationary_light_bits");
        EXPECT_NE(std::string(e.what()).find("from 64 to 74 bits"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("levoy.stationary_light_bits=0"), std::string::npos) << e.what();
    }
    // Too large either way: the backing store is what to change.
    try {
        LevoyRenderer::check_fits(machine, glm::ivec3(64, 64, 40), settings);
        FAIL() << "40 slots do not fit";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "renderer.backing_store_bits");
    }
}

// Building the pyramid is modelled work: the PPs mark each voxel's emptiness, each renderer reads out a
// bit plane a slot and broadcasts it, and every GP builds. Without skipping the machine builds nothing.
TEST(LevoyRenderer, APyramidBuildChargesTheEmptinessPassAndItsReadOutOnlyWhenRaysSkip) {
    const auto first_frame = [](bool skipping, std::uint64_t& read_outs, std::uint64_t& slots_used) {
        Scene s;
        s.config.set("levoy.pyramid_skipping", skipping, "test");
        Machine machine(s.config);
        LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
        LevoyFrameReport report = renderer.render(s.inputs);
        read_outs = 0;
        for (const auto& r : machine.renderers()) read_outs += r->read_outs.value();
        slots_used = 0;
        for (const Phase& phase : report.work.machine.phases)
            if (const auto* broadcast = std::get_if<BroadcastPhase>(&phase.work))
                for (std::uint32_t m : broadcast->messages_per_renderer) slots_used += m;
        return report;
    };
    std::uint64_t read_outs = 0, slots_used = 0;
    const LevoyFrameReport skipping = first_frame(true, read_outs, slots_used);
    std::vector<std::string> names;
    for (const Phase& phase : skipping.work.machine.phases) names.push_back(phase.name);
    const auto at = [&](const std::string& name) {
        return std::find(names.begin(), names.end(), name) - names.begin();
    };
    ASSERT_LT(at("emptiness"), static_cast<std::ptrdiff_t>(names.size()));
    EXPECT_LT(at("classification"), at("emptiness"));
    EXPECT_LT(at("emptiness"), at("pyramid"));
    EXPECT_TRUE(skipping.pyramid_rebuilt);
    EXPECT_GT(skipping.pyramid_ps, 0u);
    EXPECT_GT(slots_used, 0u);
    EXPECT_EQ(read_outs, slots_used);  // a bit plane per slot a renderer holds

    const LevoyFrameReport plain = first_frame(false, read_outs, slots_used);
    for (const Phase& phase : plain.work.machine.phases) {
        EXPECT_NE(phase.name, "emptiness");
        EXPECT_NE(phase.name, "pyramid");
    }
    EXPECT_FALSE(plain.pyramid_rebuilt);
    EXPECT_EQ(plain.pyramid_ps, 0u);
    EXPECT_EQ(read_outs, 0u);
    EXPECT_EQ(plain.final_image.pixels, skipping.final_image.pixels);  // skipping is exact
}

TEST(LevoyRenderer, SameImageAndStatisticsAtOneAndTwoThreads) {
    const auto run = [](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        Scene s;
        Machine machine(s.config);
        LevoyRenderer renderer(machine, s.volume, LevoySettings::from(s.config), s.image);
        LevoyFrameReport report = renderer.render(s.inputs);
        LevoyFrameInputs moved = s.inputs;
        moved.camera.eye += glm::vec3(20.0f, -5.0f, 0.0f);
        moved.classification_changed = false;
        moved.lighting_changed = false;
        report = renderer.render(moved);
        return std::make_pair(std::move(report), machine.statistics().dump());
    };
    const auto [one, one_stats] = run(1);
    const auto [two, two_stats] = run(2);
    EXPECT_EQ(one.final_image.pixels, two.final_image.pixels);
    EXPECT_EQ(one.end_ps, two.end_ps);
    EXPECT_EQ(one.ray_cast.samples, two.ray_cast.samples);
    EXPECT_EQ(one.ray_cast.cache_hits, two.ray_cast.cache_hits);
    EXPECT_EQ(one_stats, two_stats);
}

TEST(LevoyRenderer, WorkQueueAssignmentGivesTheSameImage) {
    Scene s;
    Machine static_machine(s.config);
    LevoyRenderer by_tiles(static_machine, s.volume, LevoySettings::from(s.config), s.image);
    const LevoyFrameReport a = by_tiles.render(s.inputs);
    s.config.apply_override("levoy.ray_assignment=work_queue");
    Machine queue_machine(s.config);
    LevoyRenderer by_queue(queue_machine, s.volume, LevoySettings::from(s.config), s.image);
    const LevoyFrameReport b = by_queue.render(s.inputs);
    EXPECT_EQ(a.final_image.pixels, b.final_image.pixels);
    EXPECT_EQ(a.ray_cast.rays, b.ray_cast.rays);
    EXPECT_NE(a.end_ps, b.end_ps);
    nlohmann::json stats = queue_machine.statistics();
    EXPECT_GT(stats["ring"]["messages"]["value"]["command"].get<std::uint64_t>(), 0u);
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// The rays each GP cast in the last frame, fewest and most.
std::pair<std::uint64_t, std::uint64_t> rays_per_gp(const Machine& machine) {
    std::uint64_t fewest = ~0ull, most = 0;
    for (const auto& gp : machine.gps()) {
        fewest = std::min<std::uint64_t>(fewest, gp->items.value());
        most = std::max<std::uint64_t>(most, gp->items.value());
    }
    return {fewest, most};
}

TEST(LevoyRenderer, InterleavedTilesSpreadTheRaysOverTheGps) {
    // Nine tiles a row and nine GPs: in raster order each GP gets one column of tiles.
    Scene s;
    s.config.apply_override("levoy.tile_pixels=8");
    s.config.apply_override("gp.count=9");
    s.config.apply_override("levoy.ray_assignment=static_tiles");
    Machine by_columns(s.config);
    LevoyRenderer columns(by_columns, s.volume, LevoySettings::from(s.config), s.image);
    const LevoyFrameReport a = columns.render(s.inputs);
    s.config.apply_override("levoy.ray_assignment=interleaved_tiles");
    Machine interleaved(s.config);
    LevoyRenderer skewed(interleaved, s.volume, LevoySettings::from(s.config), s.image);
    const LevoyFrameReport b = skewed.render(s.inputs);
    EXPECT_EQ(a.final_image.pixels, b.final_image.pixels);
    EXPECT_EQ(a.ray_cast.rays, b.ray_cast.rays);
    const auto [a_fewest, a_most] = rays_per_gp(by_columns);
    const auto [b_fewest, b_most] = rays_per_gp(interleaved);
    EXPECT_LT(b_most - b_fewest, a_most - a_fewest)
        << "columns " << a_fewest << ".." << a_most << ", interleaved " << b_fewest << ".." << b_most;
}

}  // namespace
}  // namespace pp5
