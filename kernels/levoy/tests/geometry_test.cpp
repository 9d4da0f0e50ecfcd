// Levoy's 3D scan-conversion of polygons: coverage from subvoxel translations against the polygon's
// area, binary voxelisation at J = 1, the PPs' fixed-point counts against the host's, volume matting
// in closed form, and polygons that lie between voxel centres or have no area.

#include "kernels/levoy/geometry_programs.h"
#include "kernels/levoy/levoy_renderer.h"
#include "kernels/levoy/polygon_candidates.h"
#include "kernels/levoy/tests/levoy_test_support.h"
#include "scene/render/polygon.h"
#include "scene/volume/phantoms.h"
#include "sim/core/input_error.h"
#include "sim/core/work_progress.h"
#include "sim/machine/machine.h"

#include "sim/timing/one_processor.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace pp5 {
namespace {

PolygonSpec triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 color = glm::vec3(1.0f, 0.0f, 0.0f),
                     float opacity = 1.0f) {
    return PolygonSpec{{a, b, c}, {color}, {opacity}};
}

// Sum of host coverage fractions over every voxel of a box around the polygon.
double host_coverage_sum(const PreparedPolygon& p, int samples) {
    const auto offsets = subvoxel_offsets(samples);
    double sum = 0.0;
    const glm::ivec3 lo = glm::ivec3(glm::floor(p.lower)) - 2;
    const glm::ivec3 hi = glm::ivec3(glm::ceil(p.upper)) + 2;
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) sum += host_coverage(p, offsets, {x, y, z});
    return sum / samples;
}

// A polygon reaching far past the volume costs a sequential scan-converter only its part inside: the
// area clipped to the box, exact for a square cut in half and for one wholly inside, and bounded for
// one a billion voxels across (whose full area would make its count of operations overflow).
TEST(PolygonArea, OnlyThePartInsideTheVolumeCounts) {
    const std::vector<glm::vec3> square = {{0, 0, 5}, {10, 0, 5}, {10, 10, 5}, {0, 10, 5}};
    EXPECT_NEAR(area_inside_box(square, glm::dvec3(-1), glm::dvec3(20)), 100.0, 1e-9);
    EXPECT_NEAR(area_inside_box(square, glm::dvec3(-1), glm::dvec3(5, 20, 20)), 50.0, 1e-9);
    EXPECT_EQ(area_inside_box(square, glm::dvec3(11, -1, -1), glm::dvec3(20)), 0.0);
    const std::vector<glm::vec3> huge = {{0, 0, 0}, {9e8f, 0, 0}, {0, 9e8f, 0}};
    EXPECT_NEAR(area_inside_box(huge, glm::dvec3(-1), glm::dvec3(32)), 32.0 * 32.0,
                1e-6);  // the box's quarter of x, y >= 0
}

TEST(ScanConversion, CoverageApproachesTheAreaAsTranslationsGrow) {
    // A tilted triangle of area about 200 voxels^2.
    const PreparedPolygon p = prepare_polygon(triangle({3.2f, 4.1f, 5.3f}, {24.7f, 6.2f, 11.9f}, {9.4f, 22.8f, 17.1f}));
    double previous_error = 1e9;
    for (const int samples : {1, 8, 64, 512}) {
        const double error = std::abs(host_coverage_sum(p, samples) - p.area) / p.area;
        if (samples >= 8) {
            EXPECT_LT(error, previous_error + 0.002) << samples;
        }
        previous_error = error;
        if (samples == 64) {
            EXPECT_LT(error, 0.02);
        }
        if (samples == 512) {
            EXPECT_LT(error, 0.005);
        }
        RecordProperty("relative_error_J" + std::to_string(samples), std::to_string(error));
    }
}

TEST(ScanConversion, OneTranslationIsABinaryVoxelisationOfTheCentres) {
    const PreparedPolygon p = prepare_polygon(triangle({2.0f, 2.0f, 3.4f}, {14.0f, 3.0f, 5.0f}, {5.0f, 13.0f, 8.0f}));
    const auto offsets = subvoxel_offsets(1);
    ASSERT_EQ(offsets[0], glm::dvec3(0.0));
    for (int z = 0; z < 12; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const int c = host_coverage(p, offsets, {x, y, z});
                EXPECT_EQ(c, p.in_sheet(glm::dvec3(x, y, z)) ? 1 : 0);
            }
}

TEST(ScanConversion, PolygonBetweenVoxelCentresSplitsItsCoverage) {
    // Edge-on to the grid: the plane z = 10.5 lies exactly between two layers of voxel centres.
    const PreparedPolygon p = prepare_polygon(
        PolygonSpec{{{4, 4, 10.5f}, {20, 4, 10.5f}, {20, 20, 10.5f}, {4, 20, 10.5f}}, {glm::vec3(1.0f)}, {1.0f}});
    const auto offsets = subvoxel_offsets(64);
    double lower = 0.0, upper = 0.0;
    for (int y = 0; y < 25; ++y)
        for (int x = 0; x < 25; ++x) {
            lower += host_coverage(p, offsets, {x, y, 10});
            upper += host_coverage(p, offsets, {x, y, 11});
            EXPECT_EQ(host_coverage(p, offsets, {x, y, 9}), 0);
        }
    EXPECT_NEAR((lower + upper) / 64.0, p.area, 0.03 * p.area);
    EXPECT_NEAR(lower / (lower + upper), 0.5, 0.1);
}

TEST(ScanConversion, BadPolygonsAreRejectedAndDegenerateOnesCoverNothing) {
    const auto why = [](const PolygonSpec& p) {
        try {
            validate_polygon(p, "scene.toml", "polygons[0]");
        } catch (const InputError& e) {
            return e.field() + ": " + e.reason();
        }
        return std::string("accepted");
    };
    EXPECT_NE(why(PolygonSpec{{{0, 0, 0}, {1, 0, 0}}, {glm::vec3(1.0f)}, {1.0f}}).find("three vertices"),
              std::string::npos);
    EXPECT_NE(why(triangle({0, 0, 0}, {NAN, 1, 0}, {0, 1, 0})).find("finite"), std::string::npos);
    EXPECT_NE(why(PolygonSpec{{{0, 0, 0}, {4, 0, 0}, {1, 1, 0}, {0, 4, 0}}, {glm::vec3(1.0f)}, {1.0f}}).find("convex"),
              std::string::npos);
    EXPECT_NE(why(PolygonSpec{{{0, 0, 0}, {4, 0, 0}, {4, 4, 1}, {0, 4, 0}}, {glm::vec3(1.0f)}, {1.0f}}).find("plane"),
              std::string::npos);
    EXPECT_NE(why(triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, glm::vec3(2.0f))).find("[0, 1]"), std::string::npos);
    const PolygonSpec collinear = triangle({0, 0, 0}, {2, 2, 2}, {5, 5, 5});
    EXPECT_EQ(why(collinear), "accepted");
    const PreparedPolygon p = prepare_polygon(collinear);
    EXPECT_TRUE(p.degenerate);
    EXPECT_EQ(host_coverage(p, subvoxel_offsets(8), {2, 2, 2}), 0);
}

MachineConfig scan_conversion_machine(std::initializer_list<std::string_view> overrides = {}) {
    return test::levoy_config({"renderer.count=4", "renderer.pp_columns=32", "renderer.pp_rows=32", "gp.count=2"},
                              overrides);
}

// The 32^3 test volumes seen from the front, parallel.
Camera front_view() {
    Camera camera;
    camera.eye = glm::vec3(15.5f, -60.0f, 15.5f);
    camera.target = glm::vec3(15.5f);
    camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
    camera.view_height = 40.0f;
    return camera;
}

// A 32^3 volume that classifies to nothing (opacity 0), shaded grey, with `polygons` scan-converted in.
ShadedVolume scan_converted(const std::vector<PolygonSpec>& polygons, int samples) {
    const MachineConfig config = scan_conversion_machine({"levoy.jitter_samples=" + std::to_string(samples)});
    Machine machine(config);
    const Volume volume = make_constant_volume(glm::ivec3(32), 50.0f);
    LevoyRenderer renderer(machine, volume, LevoySettings::from(config),
                           LevoyImageSettings{16, 16, 1.0f, 0.95f, glm::vec3(0.0f)});
    renderer.set_polygons(polygons);
    LevoyFrameInputs in;
    in.camera = front_view();
    in.classification.contours = {{200.0f, 1.0f, 1.0f}};  // far from 50: every voxel transparent
    in.colors = ColorMap{{{0.0f, {0.5f, 0.5f, 0.5f}}}};
    in.lighting.light_follows_camera = false;
    in.lighting.specular = 0.0f;
    const LevoyFrameReport report = renderer.render(in);
    EXPECT_EQ(report.geometry.ran, !polygons.empty());
    EXPECT_EQ(report.geometry.polygons, polygons.size());
    return renderer.shaded_volume();
}

// Levoy: on a sequential machine the cost of scan-converting a polygon is proportional to its area.
TEST(ScanConversion, OnOneProcessorItsCostGrowsInProportionToArea) {
    const auto seconds_for = [](float side, const char* voxels_per_area = "levoy.scan_voxels_per_area=2") {
        const MachineConfig config =
            scan_conversion_machine({"levoy.jitter_samples=16", "gp.sustained_mflops=1.1", voxels_per_area});
        Machine machine(config);
        const Volume volume = make_constant_volume(glm::ivec3(32), 50.0f);
        LevoyRenderer renderer(machine, volume, LevoySettings::from(config),
                               LevoyImageSettings{16, 16, 1.0f, 0.95f, glm::vec3(0.0f)});
        PolygonSpec square;
        square.vertices = {{4.0f, 4.0f, 10.0f},
                           {4.0f + side, 4.0f, 10.0f},
                           {4.0f + side, 4.0f + side, 10.0f},
                           {4.0f, 4.0f + side, 10.0f}};
        square.colors = {glm::vec3(1.0f)};
        square.opacities = {1.0f};
        renderer.set_polygons({square});
        LevoyFrameInputs in;
        in.camera = front_view();
        in.classification.contours = {{200.0f, 1.0f, 1.0f}};
        in.colors = ColorMap{{{0.0f, {0.5f, 0.5f, 0.5f}}}};
        const LevoyFrameReport report = renderer.render(in);
        const FrameTiming t = time_frame_on_one_processor(config, report.work.machine);
        return ticks_to_seconds(t.phase("scan_conversion")->duration_ps());
    };
    const double small = seconds_for(4.0f);
    EXPECT_NEAR(seconds_for(8.0f) / small, 4.0, 1e-9);
    EXPECT_NEAR(seconds_for(16.0f) / small, 16.0, 1e-9);
    // The closed form: 2 voxels per unit area, J x (edges + 1) tests of 2 flops and a 12-flop matte each.
    EXPECT_NEAR(small, 16.0 * 2.0 * (16.0 * 5.0 * 2.0 + 12.0) / 1.1e6, small * 1e-6);
    // and the voxels visited per unit area scale it.
    EXPECT_NEAR(seconds_for(4.0f, "levoy.scan_voxels_per_area=3") / small, 1.5, 1e-9);
}

TEST(ScanConversion, PixelProcessorsCountWhatTheHostCounts) {
    const PolygonSpec spec =
        triangle({3.2f, 4.1f, 5.3f}, {27.7f, 6.2f, 11.9f}, {9.4f, 26.8f, 25.1f}, glm::vec3(1.0f), 1.0f);
    const int samples = 16;
    const ShadedVolume v = scan_converted({spec}, samples);
    const PreparedPolygon p = prepare_polygon(spec);
    const auto offsets = subvoxel_offsets(samples);
    std::size_t differ = 0;
    std::size_t covered = 0;
    double coverage_sum = 0.0;
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const int count = host_coverage(p, offsets, {x, y, z});
                const int expect = 255 * count / samples;  // the PPs' integer divide
                const int got =
                    static_cast<int>(std::lround(v.rgba[static_cast<std::size_t>(x + 32 * (y + 32 * z))].a * 255.0f));
                covered += count > 0 ? 1 : 0;
                differ += got != expect ? 1 : 0;
                coverage_sum += got / 255.0;
            }
    EXPECT_GT(covered, 300u);
    // Sample points that sit on the sheet's faces to within the QEE's 2^-16 fixed point may go either way.
    EXPECT_LE(differ, covered / 100 + 2) << differ << " of " << covered;
    EXPECT_NEAR(coverage_sum, p.area, 0.06 * p.area);
}

TEST(ScanConversion, MattingFullAndZeroCoverageMatchesTheClosedForm) {
    // A square in the plane z = 10 through voxel centres: the voxels at z = 10 inside it are covered by
    // every translation (|offset.z| < 1/2), those at z = 9 and 11 by none.
    const glm::vec3 purple(0.6f, 0.2f, 0.8f);
    const PolygonSpec square{{{4, 4, 10}, {20, 4, 10}, {20, 20, 10}, {4, 20, 10}}, {purple}, {1.0f}};
    const ShadedVolume v = scan_converted({square}, 8);
    const ShadedVolume plain = scan_converted({}, 8);
    const auto at = [](const ShadedVolume& s, int x, int y, int z) {
        return s.rgba[static_cast<std::size_t>(x + 32 * (y + 32 * z))];
    };
    for (int y = 6; y <= 18; ++y)
        for (int x = 6; x <= 18; ++x) {
            const glm::vec4 full = at(v, x, y, 10);
            EXPECT_FLOAT_EQ(full.a, 1.0f);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(full[k], purple[k], 0.5f / 255.0f) << x << "," << y;
            EXPECT_EQ(at(v, x, y, 9), at(plain, x, y, 9));
            EXPECT_EQ(at(v, x, y, 11), at(plain, x, y, 11));
        }
    EXPECT_EQ(at(v, 25, 25, 10), at(plain, 25, 25, 10));
}

// Scan-converting many polygons reports its progress, polygon by polygon, to whoever listens.
TEST(ScanConversion, ReportsItsProgressPolygonByPolygon) {
    struct Recorder final : WorkListener {
        std::vector<std::size_t> done;
        void on_work(std::string_view stage, std::size_t d, std::size_t total) override {
            EXPECT_EQ(stage, "scan-converting polygons");
            EXPECT_EQ(total, 3u);
            done.push_back(d);
        }
    } recorder;
    const ScopedWorkListener listening(recorder);
    scan_converted({triangle({4, 4, 10}, {20, 4, 10}, {4, 20, 10}), triangle({4, 4, 12}, {20, 4, 12}, {4, 20, 12}),
                    triangle({4, 4, 14}, {20, 4, 14}, {4, 20, 14})},
                   1);
    EXPECT_EQ(recorder.done, (std::vector<std::size_t>{1, 2, 3}));
}

// The host runs a polygon's program only on the PPs polygon_candidates names: every PP's record, and
// the counts, must come out as a run on every PP leaves them. Random triangles and quads of every
// orientation (some in a plane of voxels, some steep, some tiny), every kind of coverage, and a slot
// reaching past the volume, where the plane's values can wrap in their fields.
TEST(ScanConversion, RunningOnlyTheCandidatesChangesNothing) {
    const glm::ivec3 dims(40, 23, 9);
    const PpArrayShape shape{1, 32, 16, 64};
    const PpProgramInputs inputs;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-3.0f, 42.0f), unit(0.0f, 1.0f);
    const auto random_polygon = [&](int kind) {
        PolygonSpec p{{}, {glm::vec3(unit(rng), unit(rng), unit(rng))}, {0.2f + 0.8f * unit(rng)}};
        const glm::vec3 a(coordinate(rng), coordinate(rng) * 0.6f, coordinate(rng) * 0.25f);
        if (kind == 0) {  // in the plane z = const, through voxel centres
            const float z = std::round(a.z);
            p.vertices = {
                {a.x, a.y, z}, {a.x + 9.0f, a.y + 1.0f, z}, {a.x + 2.0f, a.y + 8.0f, z}, {a.x - 1, a.y + 5, z}};
        } else if (kind == 1) {  // tiny
            p.vertices = {a, a + glm::vec3(0.7f, 0.2f, 0.1f), a + glm::vec3(0.1f, 0.8f, 0.4f)};
        } else {
            p.vertices = {a, a + 12.0f * glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f),
                          a + 12.0f * glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f)};
        }
        return p;
    };
    std::size_t candidates_seen = 0, pps_seen = 0, changed = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const PreparedPolygon polygon = prepare_polygon(random_polygon(trial % 4 == 0 ? 0 : trial % 4 == 1 ? 1 : 2));
        if (polygon.degenerate) continue;
        const int samples = std::array{1, 5, 16}[static_cast<std::size_t>(trial % 3)];
        const PpProgram program = build_polygon_program(polygon, samples, dims, inputs);
        const std::vector<glm::dvec3> offsets = subvoxel_offsets(samples);
        // A slice through the polygon's middle.
        const int z =
            std::clamp(static_cast<int>(std::round((polygon.lower.z + polygon.upper.z) / 2.0f)), 0, dims.z - 1);
        for (const glm::ivec3 origin : {glm::ivec3(0, 0, z), glm::ivec3(32, 16, z), glm::ivec3(0, 16, trial % 9)}) {
            const std::vector<QeeCoefficients> expressions =
                polygon_expressions(polygon, offsets, SlotFrame{origin, true}, inputs.layout);
            const PpSlotContext context{0, expressions};
            PpArray whole(shape.columns, shape.rows, inputs.local_memory_bits, shape.backing_store_bits);
            PpArray listed(shape.columns, shape.rows, inputs.local_memory_bits, shape.backing_store_bits);
            std::mt19937_64 records(static_cast<std::uint64_t>(trial));
            std::vector<std::uint64_t> before;
            for (int pp = 0; pp < whole.size(); ++pp) {
                before.push_back(records());
                whole.write_backing(pp, 0, 64, before.back());
                listed.write_backing(pp, 0, 64, before.back());
            }
            std::vector<int> candidates;
            polygon_candidates(polygon, samples, program, expressions, shape, candidates);
            const PpRunCounts want = whole.run(program, context);
            const PpRunCounts got = listed.run_candidates(program, context, candidates);
            for (int pp = 0; pp < whole.size(); ++pp) {
                ASSERT_EQ(listed.read_backing(pp, 0, 64), whole.read_backing(pp, 0, 64))
                    << "trial " << trial << " PP " << pp;
                changed += whole.read_backing(pp, 0, 64) != before[static_cast<std::size_t>(pp)] ? 1 : 0;
            }
            ASSERT_EQ(got.enabled_pp_operations, want.enabled_pp_operations) << "trial " << trial;
            ASSERT_EQ(got.pp_operations, want.pp_operations);
            candidates_seen += candidates.size();
            pps_seen += static_cast<std::size_t>(whole.size());
        }
    }
    // Polygons really were scan-converted, and far fewer PPs ran on the host.
    EXPECT_GT(changed, 500u) << changed;
    EXPECT_LT(candidates_seen, pps_seen / 3) << candidates_seen << " of " << pps_seen;
}

// Coordinates up to kFarthestPolygonVertex reach the renderers' fixed-point fields intact (a plane
// through the volume, and a tilted one far outside it); farther ones are the user's mistake.
TEST(ScanConversion, TheFarthestAcceptedVerticesFitThePixelProcessorsFields) {
    const float far = static_cast<float>(kFarthestPolygonVertex);
    const PolygonSpec across = triangle({-far, -far, 10}, {far, -far, 10}, {0, far, 10});
    const PolygonSpec tilted = triangle({far, far, far}, {far, -far, far}, {-far, far, -far});
    const ShadedVolume v = scan_converted({across, tilted}, 1);
    EXPECT_FLOAT_EQ(v.rgba[static_cast<std::size_t>(16 + 32 * (16 + 32 * 10))].a, 1.0f);  // the plane z = 10 is covered

    try {
        validate_polygon(triangle({0, 0, 10}, {10 * far, 0, 10}, {0, 1, 10}), "scene.toml", "polygons[0]");
        FAIL() << "a vertex beyond the fixed-point range was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "polygons[0].vertices");
        EXPECT_NE(e.reason().find("fixed-point"), std::string::npos) << e.reason();
    }
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// A 32^3 volume whose every voxel classifies to opacity 0.5, with an optional region applied.
struct RegionRun {
    ShadedVolume volume;
    LevoyFrameReport report;
};

RegionRun with_region(const std::optional<RegionOfInterest>& region,
                      const Volume& volume = make_constant_volume(glm::ivec3(32), 50.0f)) {
    const MachineConfig config = scan_conversion_machine();
    Machine machine(config);
    LevoyRenderer renderer(machine, volume, LevoySettings::from(config),
                           LevoyImageSettings{16, 16, 1.0f, 0.95f, glm::vec3(0.0f)});
    LevoyFrameInputs in;
    in.camera = front_view();
    in.classification.kind = ClassificationKind::PiecewiseLinear;
    in.classification.points = {{0.0f, 0.5f}, {255.0f, 0.5f}};
    in.colors = ColorMap{{{0.0f, {0.5f, 0.5f, 0.5f}}}};
    in.region = region;
    RegionRun run;
    run.report = renderer.render(in);
    run.volume = renderer.shaded_volume();
    return run;
}

TEST(RegionOfInterest, ScaleOneLeavesEveryVoxelAsItWas) {
    RegionOfInterest unit;
    unit.center = glm::vec3(12.0f, 15.0f, 17.0f);
    unit.half_size = glm::vec3(6.0f, 4.0f, 8.0f);
    unit.rotation_degrees = glm::vec3(10.0f, 20.0f, 30.0f);
    for (const auto shape : {RegionOfInterest::Shape::Box, RegionOfInterest::Shape::Ellipsoid}) {
        unit.shape = shape;
        const RegionRun with = with_region(unit);
        EXPECT_TRUE(with.report.region.ran);
        EXPECT_EQ(with.volume.rgba, with_region(std::nullopt).volume.rgba);
    }
}

TEST(RegionOfInterest, PixelProcessorsScaleOpacityAsTheHostModelSays) {
    for (const auto shape : {RegionOfInterest::Shape::Box, RegionOfInterest::Shape::Ellipsoid}) {
        RegionOfInterest cut;
        cut.shape = shape;
        cut.center = glm::vec3(15.0f, 14.0f, 16.0f);
        cut.half_size = glm::vec3(8.0f, 6.0f, 7.0f);
        cut.rotation_degrees = glm::vec3(0.0f, 0.0f, 25.0f);
        cut.scale_inside = 0.02f;
        cut.scale_outside = 1.0f;
        cut.transition = 3.0f;
        const RegionRun run = with_region(cut);
        const float base = run.volume.rgba[0].a;  // a corner voxel, far outside
        EXPECT_NEAR(base, 128.0f / 255.0f, 1.5f / 255.0f);
        float worst = 0.0f;
        for (int z = 0; z < 32; ++z)
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) {
                    const float expect = std::min(1.0f, base * cut.factor(glm::vec3(x, y, z)));
                    worst = std::max(
                        worst, std::abs(run.volume.rgba[static_cast<std::size_t>(x + 32 * (y + 32 * z))].a - expect));
                }
        EXPECT_LE(worst, 2.5f / 255.0f) << "shape " << static_cast<int>(shape);
        const glm::ivec3 c(cut.center);
        EXPECT_LE(run.volume.rgba[static_cast<std::size_t>(c.x + 32 * (c.y + 32 * c.z))].a, 3.0f / 255.0f);
    }
}

// Levoy's capping: the transition zone is shaded as if the region held air. In a volume of 50 with one
// voxel of 0 (air) far from the region, a voxel in one face's band has gradient (50 - 0) / 2 along the
// face's outward normal n, so its normal is -n (into the region): the back wall of the cut faces the
// light and is lit, the front wall is not. Everywhere else the colours are those of the uncapped run.
TEST(RegionOfInterest, CappingShadesTheTransitionZoneAsIfTheRegionHeldAir) {
    std::vector<float> samples(32 * 32 * 32, 50.0f);
    samples[0] = 0.0f;
    const Volume volume(glm::ivec3(32), glm::vec3(1.0f), ScalarType::UInt8, samples);
    RegionOfInterest cut;
    cut.center = glm::vec3(16.0f, 16.0f, 16.0f);
    cut.half_size = glm::vec3(6.0f);
    cut.scale_inside = 0.02f;
    cut.transition = 3.0f;
    const RegionRun plain = with_region(cut, volume);
    cut.cap = true;
    const RegionRun capped = with_region(cut, volume);

    const LevoyFrameInputs defaults;
    const ShadingView view = make_shading_view(front_view(), glm::ivec3(32), glm::vec3(1.0f));
    const glm::vec3 to_viewer = -view.forward;  // the default light is a headlight: L = V
    int banded = 0, lit = 0, unchanged = 0;
    float worst = 0.0f;
    for (int z = 4; z < 28; ++z)
        for (int y = 4; y < 28; ++y)
            for (int x = 4; x < 28; ++x) {
                const std::size_t i = static_cast<std::size_t>(x + 32 * (y + 32 * z));
                EXPECT_EQ(capped.volume.rgba[i].a, plain.volume.rgba[i].a);  // capping leaves opacities alone
                const glm::vec3 p(x, y, z);
                const glm::vec3 face = glm::abs(p - cut.center) - cut.half_size;
                const float distance = std::max({face.x, face.y, face.z});
                const float half = 0.5f * cut.transition;
                const int faces_in_band = (face.x > -half) + (face.y > -half) + (face.z > -half);
                if (distance >= half || faces_in_band == 0) {
                    EXPECT_EQ(capped.volume.rgba[i], plain.volume.rgba[i]) << x << " " << y << " " << z;
                    ++unchanged;
                    continue;
                }
                if (faces_in_band != 1 || distance < -half + 0.25f || distance > half - 0.25f)
                    continue;  // an edge, or a band's rim
                const int axis = face.x > -half ? 0 : face.y > -half ? 1 : 2;
                glm::vec3 normal(0.0f);
                normal[axis] = p[axis] > cut.center[axis] ? -1.0f : 1.0f;
                const glm::vec3 expect =
                    phong_shade(defaults.lighting, glm::vec3(0.5f), normal, to_viewer, to_viewer, 0.0f);
                const glm::vec3 got(capped.volume.rgba[i]);
                worst = std::max(worst, glm::length(got - expect));
                ++banded;
                lit += expect.x > 0.5f * defaults.lighting.ambient + 0.05f;
            }
    EXPECT_GT(unchanged, 1000);
    EXPECT_GT(banded, 200);
    EXPECT_GT(lit, 20);
    EXPECT_LE(worst, 4.0f / 255.0f);
}

TEST(RegionOfInterest, BadRegionsAreRejected) {
    RegionOfInterest r;
    r.half_size = glm::vec3(1.0f, 0.0f, 1.0f);
    EXPECT_THROW(validate_region(r, "s.toml", "region"), InputError);
    r.half_size = glm::vec3(1.0f);
    r.scale_inside = -1.0f;
    EXPECT_THROW(validate_region(r, "s.toml", "region"), InputError);
    r.scale_inside = 0.0f;
    r.transition = -2.0f;
    EXPECT_THROW(validate_region(r, "s.toml", "region"), InputError);
    r.transition = 0.0f;
    r.cap = true;  // capping needs a transition zone to recolour
    EXPECT_THROW(validate_region(r, "s.toml", "region"), InputError);
    r.transition = 2.0f;
    r.shape = RegionOfInterest::Shape::Ellipsoid;  // and a box's faces
    EXPECT_THROW(validate_region(r, "s.toml", "region"), InputError);
    r.shape = RegionOfInterest::Shape::Box;
    EXPECT_NO_THROW(validate_region(r, "s.toml", "region"));
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// Matting writes exactly the colour and opacity bits of its own voxel's record: scan-converting the
// same polygons again after a light change gives the same opacities and the same pyramid (a store one
// bit too wide once spilled into the next slot's value).
TEST(ScanConversion, RepeatingAFrameReproducesTheSameVoxels) {
    const MachineConfig config = scan_conversion_machine();
    Machine machine(config);
    const Volume volume = make_head_phantom(32);
    LevoyRenderer renderer(machine, volume, LevoySettings::from(config),
                           LevoyImageSettings{16, 16, 1.0f, 0.95f, glm::vec3(0.0f)});
    renderer.set_polygons(
        {triangle({3.2f, 4.1f, 5.3f}, {27.7f, 6.2f, 11.9f}, {9.4f, 26.8f, 25.1f}, glm::vec3(0.2f, 0.3f, 1.0f), 0.7f),
         PolygonSpec{{{4, 4, 10}, {20, 4, 10}, {20, 20, 10}, {4, 20, 10}}, {glm::vec3(1.0f)}, {1.0f}}});
    LevoyFrameInputs in;
    in.camera = front_view();
    in.classification.contours = {{40.0f, 0.3f, 1.5f}, {160.0f, 0.9f, 1.5f}};
    in.lighting.light_follows_camera = false;
    const LevoyFrameReport first = renderer.render(in);
    const ShadedVolume before = renderer.shaded_volume();
    in.classification_changed = false;
    in.lighting_changed = true;
    in.lighting.ambient = 0.25f;
    const LevoyFrameReport second = renderer.render(in);
    EXPECT_TRUE(first.pyramid_rebuilt);
    EXPECT_FALSE(second.pyramid_rebuilt);
    const ShadedVolume after = renderer.shaded_volume();  // decodes the whole volume: once, not per voxel
    ASSERT_EQ(before.rgba.size(), after.rgba.size());
    for (std::size_t i = 0; i < before.rgba.size(); ++i) ASSERT_EQ(before.rgba[i].a, after.rgba[i].a) << "voxel " << i;
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// Antialiasing: per-voxel coverage against a finely filtered reference (4096 translations), over the
// voxels any of them touches. J = 1 can only say 0 or 1; more translations approach the fraction.
TEST(ScanConversion, MoreTranslationsAntialiasTheEdges) {
    const PreparedPolygon p = prepare_polygon(triangle({3.2f, 4.1f, 5.3f}, {24.7f, 6.2f, 11.9f}, {9.4f, 22.8f, 17.1f}));
    const auto fine = subvoxel_offsets(4096);
    std::vector<double> rms;
    for (const int samples : {1, 4, 16, 64}) {
        const auto offsets = subvoxel_offsets(samples);
        double sum = 0.0;
        int voxels = 0;
        for (int z = 2; z < 21; ++z)
            for (int y = 2; y < 26; ++y)
                for (int x = 1; x < 28; ++x) {
                    const double truth = host_coverage(p, fine, {x, y, z}) / 4096.0;
                    const double got = static_cast<double>(host_coverage(p, offsets, {x, y, z})) / samples;
                    if (truth == 0.0 && got == 0.0) continue;
                    sum += (got - truth) * (got - truth);
                    ++voxels;
                }
        rms.push_back(std::sqrt(sum / voxels));
        RecordProperty("rms_coverage_error_J" + std::to_string(samples), std::to_string(rms.back()));
    }
    for (std::size_t i = 1; i < rms.size(); ++i) EXPECT_LT(rms[i], rms[i - 1]);
    EXPECT_LT(rms[2], 0.5 * rms[0]);
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

TEST(ScanConversion, RepeatedVertexGivesFiniteColours) {
    const PolygonSpec square{
        {{4, 4, 10}, {4, 4, 10}, {20, 4, 10}, {20, 20, 10}, {4, 20, 10}},
        {glm::vec3(1, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), glm::vec3(1, 1, 1)},
        {1.0f}};
    EXPECT_NO_THROW(validate_polygon(square, "s.toml", "polygons[0]"));
    const PreparedPolygon p = prepare_polygon(square);
    for (const LinearFunction* f : {&p.red, &p.green, &p.blue, &p.opacity}) {
        EXPECT_TRUE(std::isfinite(f->offset));
        EXPECT_TRUE(std::isfinite(f->gradient.x) && std::isfinite(f->gradient.y) && std::isfinite(f->gradient.z));
    }
}

TEST(ScanConversion, ColourBeyondASmallPolygonClampsInsteadOfWrapping) {
    // A sub-voxel triangle, red at one corner only: voxels its sheet reaches lie up to a voxel
    // outside it, where the linear red runs far below 0; the PPs clamp it to 0.
    const PolygonSpec tiny{{{10.45f, 10.45f, 10.0f}, {10.75f, 10.45f, 10.0f}, {10.45f, 10.75f, 10.0f}},
                           {glm::vec3(1, 0, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, 0)},
                           {1.0f}};
    const PreparedPolygon p = prepare_polygon(tiny);
    const auto offsets = subvoxel_offsets(64);
    ASSERT_GT(host_coverage(p, offsets, {11, 11, 10}), 0);
    ASSERT_LT(p.red(glm::vec3(11, 11, 10)), 0.0f);
    const ShadedVolume v = scan_converted({tiny}, 64);
    EXPECT_LT(v.rgba[static_cast<std::size_t>(11 + 32 * (11 + 32 * 10))].r, 0.5f / 255.0f);
}

}  // namespace
}  // namespace pp5
