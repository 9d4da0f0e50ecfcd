// Levoy's classification and shading on the simulated PPs: the fixed-point results against the
// floating-point reference, the passes that each kind of change reruns, the simulated time against
// the cost model, determinism across thread counts, and the errors for a machine too small.

#include "kernels/shared/pp_volume/pp_shading.h"
#include "frontends/image_io.h"
#include "kernels/levoy/tests/levoy_test_support.h"
#include "scene/reference/composite.h"
#include "scene/reference/reference_renderer.h"
#include "scene/reference/voxel_opacity.h"
#include "scene/volume/phantoms.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"
#include "tests/unit/render/test_scenes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

namespace pp5 {
namespace {

// A small machine so tests run in milliseconds: 4 renderers of 32x32 PPs, 2048 bits of backing store.
MachineConfig pp_shading_machine(std::initializer_list<std::string_view> overrides = {}) {
    return test::levoy_config(
        {"renderer.count=4", "renderer.pp_columns=32", "renderer.pp_rows=32", "renderer.backing_store_bits=2048"},
        overrides);
}

Classification skin_contour() {
    Classification c;
    c.kind = ClassificationKind::IsovalueContours;
    c.contours = {{100.0f, 0.9f, 1.5f}};
    return c;
}

PhongLighting phong() {
    PhongLighting l;
    l.ambient = 0.15f;
    l.diffuse = 0.7f;
    l.specular = 0.3f;
    l.shininess = 12.0f;
    l.depth_cue_k1 = 1.0f;
    l.depth_cue_k2 = 0.5f;
    return l;
}

Camera oblique_camera(const Volume& v) {
    Camera c;
    c.projection = Projection::Parallel;
    const glm::vec3 center = test::box_center(v);
    c.eye = center + glm::vec3(-300.0f, -200.0f, -500.0f);
    c.target = center;
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    c.view_height = 2.2f * test::box_radius(v);
    return c;
}

struct Rendered {
    Image machine;
    Image reference;
    PpFrameReport report;
};

Rendered render_both(const Volume& volume, const Classification& classification, const ColorMap& colors,
                     const PhongLighting& lighting, const MachineConfig& config) {
    Machine machine(config);
    PpShading pps(machine, volume, VoxelStoreSettings::from(config));
    const Camera camera = oblique_camera(volume);
    RenderSettings settings;
    settings.width = 96;
    settings.height = 80;
    const ShadingView view = make_shading_view(camera, volume.dims(), volume.spacing());
    Rendered out;
    out.report = pps.update(classification, colors, lighting, view, true, true);
    out.machine = composite(pps.shaded_volume(), camera, settings.composite_settings());
    ReferenceRenderer reference(volume);
    reference.set_classification(classification, colors);
    reference.set_lighting(lighting);
    out.reference = reference.render(camera, settings);
    return out;
}

const ColorMap kWarm{{{0.0f, {0.9f, 0.6f, 0.5f}}, {255.0f, {1.0f, 1.0f, 0.9f}}}};

TEST(PpShading, IsovalueContourImageMatchesTheReference) {
    const Volume ball = test::ball_volume(glm::ivec3(40, 36, 30), glm::vec3(19.5f, 17.0f, 14.5f), 12.0f);
    const Rendered r = render_both(ball, skin_contour(), kWarm, phong(), pp_shading_machine());
    const ImageDifference d = compare_images(r.machine, r.reference);
    EXPECT_GE(d.psnr_db, 35.0) << "rms " << d.rms_error << " max " << d.max_error;
    EXPECT_TRUE(r.report.classification.ran);
    EXPECT_TRUE(r.report.shading.ran);
}

TEST(PpShading, PiecewiseAndRegionBoundaryImagesMatchTheReference) {
    const Volume lumpy = test::lumpy_volume(glm::ivec3(33, 31, 29));
    Classification ramp = test::piecewise({{20.0f, 0.0f}, {120.0f, 0.8f}});
    Classification boundary;
    boundary.kind = ClassificationKind::RegionBoundaries;
    boundary.points = {{0.0f, 0.0f}, {90.0f, 0.02f}, {170.0f, 0.05f}};
    for (const Classification& c : {ramp, boundary}) {
        const Rendered r = render_both(lumpy, c, kWarm, phong(), pp_shading_machine());
        const ImageDifference d = compare_images(r.machine, r.reference);
        EXPECT_GE(d.psnr_db, 35.0) << "kind " << static_cast<int>(c.kind) << " rms " << d.rms_error;
    }
}

// Voxel by voxel against the reference's shade_voxels: colours within a few codes wherever the voxel
// is visible, including flat interiors (no gradient: ambient light only).
void voxel_colours_match_the_reference(const MachineConfig& config) {
    SCOPED_TRACE(config.integer("voxel_store.color_bits"));
    const Volume sphere = make_sphere_phantom(32);
    const Classification ramp = test::piecewise({{50.0f, 0.0f}, {150.0f, 0.8f}});
    Machine machine(config);
    PpShading pps(machine, sphere, VoxelStoreSettings::from(config));
    const ShadingView view = make_shading_view(oblique_camera(sphere), sphere.dims(), sphere.spacing());
    pps.update(ramp, kWarm, phong(), view, true, true);
    const ShadedVolume machine_colours = pps.shaded_volume();
    const GradientField gradients = compute_gradients(sphere);
    const std::vector<float> opacities = classify_voxels(sphere, gradients, ramp);
    const ShadedVolume reference = shade_voxels(sphere, gradients, opacities, kWarm, phong(), view);
    float worst_colour = 0.0f;
    float worst_opacity = 0.0f;
    std::size_t flat_opaque = 0;
    for (std::size_t i = 0; i < opacities.size(); ++i) {
        if (opacities[i] <= 0.0f) continue;
        worst_opacity = std::max(worst_opacity, std::abs(machine_colours.rgba[i].a - reference.rgba[i].a));
        for (int c = 0; c < 3; ++c)
            worst_colour = std::max(worst_colour, std::abs(machine_colours.rgba[i][c] - reference.rgba[i][c]));
        flat_opaque += gradients.gradients[i] == glm::vec3(0.0f) ? 1 : 0;
    }
    EXPECT_GT(flat_opaque, 500u) << "the test needs flat opaque voxels";
    // Within two opacity codes: the value is stored to the nearest code (half a unit on this ramp of
    // 0.008 per unit) and the opacity rounded to 1/255.
    EXPECT_LE(worst_opacity, 2.0f / 255.0f);
    EXPECT_LE(worst_colour, 0.06f);
}

// Both ways of reading the codes back: 8-bit colours (copied as they lie) and 10-bit ones (taken apart
// channel by channel).
TEST(PpShading, VoxelColoursAndOpacitiesMatchTheReference) {
    for (const std::string_view bits : {"voxel_store.color_bits=8", "voxel_store.color_bits=10"})
        voxel_colours_match_the_reference(pp_shading_machine({bits}));
}

TEST(PpShading, EachChangeRerunsOnlyItsPass) {
    const Volume ball = test::ball_volume(glm::ivec3(24), glm::vec3(11.5f), 8.0f);
    const MachineConfig config = pp_shading_machine();
    Machine machine(config);
    PpShading pps(machine, ball, VoxelStoreSettings::from(config));
    const Camera camera = oblique_camera(ball);
    const ShadingView view = make_shading_view(camera, ball.dims(), ball.spacing());
    pps.update(skin_contour(), kWarm, phong(), view, true, true);
    const ShadedVolume first = pps.shaded_volume();

    PhongLighting brighter = phong();
    brighter.ambient = 0.4f;
    const PpFrameReport light_only = pps.update(skin_contour(), kWarm, brighter, view, false, true);
    EXPECT_FALSE(light_only.classification.ran);
    EXPECT_TRUE(light_only.shading.ran);
    EXPECT_GT(light_only.duration_ps(), 0);
    const ShadedVolume relit = pps.shaded_volume();
    bool colour_changed = false;
    for (std::size_t i = 0; i < first.rgba.size(); ++i) {
        ASSERT_EQ(first.rgba[i].a, relit.rgba[i].a) << "opacity changed with the light at voxel " << i;
        colour_changed |= first.rgba[i].r != relit.rgba[i].r;
    }
    EXPECT_TRUE(colour_changed);

    Classification thinner = skin_contour();
    thinner.contours[0].thickness = 0.7f;
    const PpFrameReport class_only = pps.update(thinner, kWarm, brighter, view, true, false);
    EXPECT_TRUE(class_only.classification.ran);
    EXPECT_FALSE(class_only.shading.ran);
    const ShadedVolume reclassified = pps.shaded_volume();
    bool opacity_changed = false;
    for (std::size_t i = 0; i < relit.rgba.size(); ++i) {
        ASSERT_EQ(glm::vec3(relit.rgba[i]), glm::vec3(reclassified.rgba[i]))
            << "colour changed with the classification";
        opacity_changed |= relit.rgba[i].a != reclassified.rgba[i].a;
    }
    EXPECT_TRUE(opacity_changed);
}

TEST(PpShading, SimulatedTimeIsTheCostModelsPassOnTheBusiestRenderer) {
    const Volume ball = test::ball_volume(glm::ivec3(64, 64, 16), glm::vec3(31.5f, 31.5f, 7.5f), 20.0f);
    const MachineConfig config = pp_shading_machine();
    Machine machine(config);
    PpShading pps(machine, ball, VoxelStoreSettings::from(config));
    // 64x64 in x, y is 2x2 tiles of 32x32, 16 slices: 64 units over 4 renderers, 16 slots each.
    EXPECT_EQ(pps.placement().slots_needed(), 16);
    const Camera camera = oblique_camera(ball);
    const PpFrameReport report =
        pps.update(skin_contour(), kWarm, phong(), make_shading_view(camera, ball.dims(), ball.spacing()), true, true);
    const Renderer& renderer = *machine.renderers()[0];
    const PpPassCycles classify = renderer.cost_model().pass(report.classification.slot_cost, 16);
    const PpPassCycles shade = renderer.cost_model().pass(report.shading.slot_cost, 16);
    EXPECT_EQ(report.classification.busiest.total, classify.total);
    EXPECT_EQ(report.duration_ps(), renderer.clock().cycles_to_ticks(classify.total + shade.total));
    EXPECT_EQ(classify.total, classify.alu + classify.controller + classify.backing_store_stall);
    EXPECT_GT(report.classification.slot_cost.alu_cycles, 0u);
    EXPECT_EQ(machine.events().now(), report.end_ps);
}

TEST(PpShading, SameResultsAtOneAndTwoThreads) {
    const Volume lumpy = test::lumpy_volume(glm::ivec3(45, 38, 21));
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        const MachineConfig config = pp_shading_machine({"voxel_store.placement=slices"});
        Machine machine(config);
        PpShading pps(machine, lumpy, VoxelStoreSettings::from(config));
        const Camera camera = oblique_camera(lumpy);
        const PpFrameReport report = pps.update(skin_contour(), kWarm, phong(),
                                                make_shading_view(camera, lumpy.dims(), lumpy.spacing()), true, true);
        return std::make_pair(pps.shaded_volume(), report.duration_ps());
    };
    const auto one = run(1);
    const auto two = run(2);
    EXPECT_EQ(one.second, two.second);
    ASSERT_EQ(one.first.rgba.size(), two.first.rgba.size());
    EXPECT_EQ(0, std::memcmp(one.first.rgba.data(), two.first.rgba.data(), one.first.rgba.size() * sizeof(glm::vec4)));
}

// A key light to move and two stationary ones, one dimmed.
PhongLighting with_stationary_lights() {
    PhongLighting l = phong();
    l.light_follows_camera = false;
    l.light_direction = glm::normalize(glm::vec3(0.4f, -0.3f, -1.0f));
    l.stationary_lights = {{glm::vec3(-1.0f, 0.5f, -0.5f), 0.6f}, {glm::vec3(0.2f, 1.0f, -0.3f), 0.8f}};
    return l;
}

TEST(PpShading, StationaryLightImageMatchesTheReference) {
    const Volume ball = test::ball_volume(glm::ivec3(40, 36, 30), glm::vec3(19.5f, 17.0f, 14.5f), 12.0f);
    const Rendered r = render_both(ball, skin_contour(), kWarm, with_stationary_lights(), pp_shading_machine());
    const ImageDifference d = compare_images(r.machine, r.reference);
    EXPECT_GE(d.psnr_db, 35.0) << "rms " << d.rms_error << " max " << d.max_error;
    const Rendered key_only = render_both(
        ball, skin_contour(), kWarm,
        [] {
            PhongLighting l = with_stationary_lights();
            l.stationary_lights.clear();
            return l;
        }(),
        pp_shading_machine());
    EXPECT_LT(compare_images(r.machine, key_only.machine).psnr_db, 30.0) << "the stationary lights should show";
}

// Kept in the record, the stationary lights' sum gives exactly the colours that recomputing it does;
// a move of the key light alone then skips the stationary pass and shades in fewer cycles.
TEST(PpShading, KeptStationaryLightsGiveTheSameColoursAndCheaperKeyLightMoves) {
    const Volume ball = test::ball_volume(glm::ivec3(24), glm::vec3(11.5f), 8.0f);
    const MachineConfig config = pp_shading_machine();
    VoxelStoreSettings keeping = VoxelStoreSettings::from(config);
    keeping.layout.stationary_light_bits = 10;
    Machine kept_machine(config), recomputing_machine(config);
    PpShading kept(kept_machine, ball, keeping);
    PpShading recomputed(recomputing_machine, ball, VoxelStoreSettings::from(config));
    const ShadingView view = make_shading_view(oblique_camera(ball), ball.dims(), ball.spacing());
    const auto both = [&](const PhongLighting& lighting, bool classify) {
        const PpFrameReport a = kept.update(skin_contour(), kWarm, lighting, view, classify, true);
        const PpFrameReport b = recomputed.update(skin_contour(), kWarm, lighting, view, classify, true);
        EXPECT_EQ(kept.shaded_volume().rgba, recomputed.shaded_volume().rgba);
        EXPECT_FALSE(b.stationary_lights.ran);
        return std::pair{a, b};
    };
    PhongLighting lighting = with_stationary_lights();
    EXPECT_TRUE(both(lighting, true).first.stationary_lights.ran);

    lighting.light_direction = glm::normalize(glm::vec3(-0.6f, 0.1f, -0.8f));
    const auto [moved, moved_recomputed] = both(lighting, false);
    EXPECT_FALSE(moved.stationary_lights.ran);
    EXPECT_LT(moved.shading.slot_cost.compute_cycles(), moved_recomputed.shading.slot_cost.compute_cycles());
    EXPECT_LT(moved.duration_ps(), moved_recomputed.duration_ps());

    lighting.stationary_lights[1].intensity = 0.3f;  // a stationary light dims: its sum is stored again
    EXPECT_TRUE(both(lighting, false).first.stationary_lights.ran);
    lighting.specular = 0.1f;  // so does a change of k_s
    EXPECT_TRUE(both(lighting, false).first.stationary_lights.ran);
    lighting.ambient = 0.3f;  // but not of k_a, which the sum leaves out
    EXPECT_FALSE(both(lighting, false).first.stationary_lights.ran);

    // With a highlight the sum depends on the view's direction: a new view stores it again.
    ASSERT_GT(lighting.specular, 0.0f);
    Camera turned = oblique_camera(ball);
    turned.eye = test::box_center(ball) + glm::vec3(400.0f, -150.0f, -300.0f);
    const ShadingView turned_view = make_shading_view(turned, ball.dims(), ball.spacing());
    const PpFrameReport a = kept.update(skin_contour(), kWarm, lighting, turned_view, false, true);
    recomputed.update(skin_contour(), kWarm, lighting, turned_view, false, true);
    EXPECT_TRUE(a.stationary_lights.ran);
    EXPECT_EQ(kept.shaded_volume().rgba, recomputed.shaded_volume().rgba);
}

TEST(PpShading, AVolumeTooLargeIsAnErrorSayingWhatWouldFit) {
    const Volume big = test::constant_volume(glm::ivec3(64, 64, 40), 10.0f);
    const MachineConfig config = pp_shading_machine();
    Machine machine(config);
    try {
        PpShading pps(machine, big, VoxelStoreSettings::from(config));
        FAIL() << "a 64x64x40 volume needs 40 slots of 64 bits; the small machine has 32";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "renderer.backing_store_bits");
        EXPECT_NE(std::string(e.what()).find("40 slots"), std::string::npos) << e.what();
    }
}

TEST(PpShading, AProgramTooLargeForLocalMemoryIsAnError) {
    const Volume ball = test::ball_volume(glm::ivec3(16), glm::vec3(7.5f), 5.0f);
    const MachineConfig config = pp_shading_machine({"renderer.local_memory_bits=48"});
    Machine machine(config);
    PpShading pps(machine, ball, VoxelStoreSettings::from(config));
    const Camera camera = oblique_camera(ball);
    try {
        pps.update(skin_contour(), kWarm, phong(), make_shading_view(camera, ball.dims(), ball.spacing()), true, true);
        FAIL() << "the programs cannot fit in 48 bits";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "renderer.local_memory_bits");
        EXPECT_NE(std::string(e.what()).find("short"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pp5
