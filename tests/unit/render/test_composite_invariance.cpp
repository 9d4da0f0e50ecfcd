// Accelerations and parallelism must not change the picture: empty-space skipping, early termination
// at 1, on-demand shading and the thread count leave every byte of the image the same.

#include "scene/reference/composite.h"
#include "scene/reference/post_classified.h"
#include "scene/reference/reference_renderer.h"
#include "scene/reference/shaded_volume.h"
#include "scene/reference/voxel_opacity.h"
#include "test_scenes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <functional>
#include <string>

namespace pp5 {
namespace {

// An odd-sized lumpy scene, a translucent ramp and an isovalue classification.
struct LumpyScene {
    const Volume volume = test::lumpy_volume({61, 53, 47});
    const GradientField gradients = compute_gradients(volume);
    const ColorMap colors{{{0.0f, {0.9f, 0.5f, 0.3f}}, {160.0f, {1.0f, 1.0f, 0.9f}}}};
    const PhongLighting lighting{};
    const std::vector<Classification> classifications = {
        test::piecewise({{20.0f, 0.0f}, {170.0f, 0.5f}}),
        [] {
            Classification c;
            c.kind = ClassificationKind::IsovalueContours;
            c.contours = {{60.0f, 0.5f, 1.5f}, {120.0f, 1.0f, 1.0f}};
            return c;
        }(),
    };

    std::vector<Camera> cameras() const {
        OrbitView perspective;
        perspective.azimuth_degrees = 30.0f;
        perspective.elevation_degrees = 20.0f;
        OrbitView parallel = perspective;
        parallel.projection = Projection::Parallel;
        parallel.azimuth_degrees = -115.0f;
        parallel.elevation_degrees = -40.0f;
        return {orbit_camera(test::box_center(volume), test::box_radius(volume), perspective),
                orbit_camera(test::box_center(volume), test::box_radius(volume), parallel)};
    }

    CompositeSettings settings(float step) const {
        CompositeSettings s;
        s.width = 67;
        s.height = 59;
        s.sample_step = step;
        return s;
    }

    Image pre(const Classification& c, const Camera& camera, const CompositeSettings& s, CompositeStats* stats) const {
        const std::vector<float> opacity = classify_voxels(volume, gradients, c);
        return composite(shade_voxels(volume, gradients, opacity, colors, lighting, camera), camera, s, stats);
    }
    Image post(const Classification& c, const Camera& camera, const CompositeSettings& s, CompositeStats* stats) const {
        return render_post_classified(volume, gradients, c, colors, lighting, camera, s, stats);
    }
};

using Renderer = std::function<Image(const LumpyScene&, const Classification&, const Camera&, const CompositeSettings&,
                                     CompositeStats*)>;

const std::vector<std::pair<std::string, Renderer>> kOrders = {
    {"shade-then-interpolate",
     [](const LumpyScene& s, const Classification& c, const Camera& cam, const CompositeSettings& st,
        CompositeStats* stats) { return s.pre(c, cam, st, stats); }},
    {"interpolate-then-shade",
     [](const LumpyScene& s, const Classification& c, const Camera& cam, const CompositeSettings& st,
        CompositeStats* stats) { return s.post(c, cam, st, stats); }},
};

TEST(Invariance, SkippingEmptySpaceChangesNoByte) {
    const LumpyScene scene;
    for (const auto& [name, render] : kOrders) {
        for (const Classification& c : scene.classifications) {
            for (const Camera& camera : scene.cameras()) {
                for (float step : {1.0f, 0.7f}) {
                    CompositeSettings on = scene.settings(step);
                    CompositeSettings off = on;
                    off.skip_empty_space = false;
                    CompositeStats with_skip;
                    CompositeStats without;
                    const Image a = render(scene, c, camera, on, &with_skip);
                    const Image b = render(scene, c, camera, off, &without);
                    SCOPED_TRACE(name + " step " + std::to_string(step));
                    EXPECT_TRUE(test::same_bytes(a, b));
                    // The same samples are accounted for: evaluated or known empty.
                    EXPECT_EQ(with_skip.samples + with_skip.samples_skipped, without.samples);
                    EXPECT_EQ(without.samples_skipped, 0u);
                    EXPECT_GT(with_skip.samples_skipped, 0u);
                    EXPECT_EQ(with_skip.rays_terminated, without.rays_terminated);
                    EXPECT_EQ(with_skip.rays_hit, without.rays_hit);
                }
            }
        }
    }
}

TEST(Invariance, EarlyTerminationAtOneChangesNoByte) {
    const LumpyScene scene;
    const Classification opaque = test::piecewise({{20.0f, 0.0f}, {100.0f, 1.0f}});
    for (const auto& [name, render] : kOrders) {
        for (const Camera& camera : scene.cameras()) {
            CompositeSettings at_one = scene.settings(1.0f);
            at_one.termination_opacity = 1.0f;
            CompositeSettings off = at_one;
            off.early_termination = false;
            CompositeStats stopped;
            CompositeStats full;
            const Image a = render(scene, opaque, camera, at_one, &stopped);
            const Image b = render(scene, opaque, camera, off, &full);
            SCOPED_TRACE(name);
            EXPECT_TRUE(test::same_bytes(a, b));
            EXPECT_GT(stopped.rays_terminated, 0u);  // rays did reach full opacity, and stopped
            EXPECT_LT(stopped.samples, full.samples);
        }
    }
}

TEST(Invariance, ThreadCountChangesNothing) {
    const LumpyScene scene;
    const Camera camera = scene.cameras()[0];
    const CompositeSettings settings = scene.settings(0.8f);
    auto run = [&](std::size_t threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<Image> images;
        std::vector<CompositeStats> stats(4);
        images.push_back(scene.pre(scene.classifications[0], camera, settings, &stats[0]));
        images.push_back(scene.post(scene.classifications[1], camera, settings, &stats[1]));
        ReferenceRenderer renderer(scene.volume);
        renderer.set_classification(scene.classifications[0], scene.colors);
        RenderSettings render_settings;
        render_settings.width = settings.width;
        render_settings.height = settings.height;
        render_settings.sample_step = settings.sample_step;
        RenderStats render_stats;
        images.push_back(renderer.render(camera, render_settings, &render_stats));
        stats[2] = render_stats.composite;
        stats[3].samples = render_stats.voxels_shaded;  // on-demand shading work, too
        return std::make_pair(images, stats);
    };
    const auto one = run(1);
    const auto two = run(2);
    for (std::size_t i = 0; i < one.first.size(); ++i) {
        EXPECT_TRUE(test::same_bytes(one.first[i], two.first[i])) << "image " << i;
        EXPECT_EQ(one.second[i], two.second[i]) << "stats " << i;
    }
}

// On-demand shading gives exactly what shading every voxel first gives, frame after frame.
TEST(Invariance, OnDemandShadingMatchesShadingEverything) {
    const LumpyScene scene;
    ReferenceRenderer renderer(scene.volume);
    renderer.set_classification(scene.classifications[1], scene.colors);
    RenderSettings settings;
    const CompositeSettings composite_settings = scene.settings(1.0f);
    settings.width = composite_settings.width;
    settings.height = composite_settings.height;
    const std::vector<float> opacity = classify_voxels(scene.volume, scene.gradients, scene.classifications[1]);
    OrbitView orbit;
    for (float azimuth : {0.0f, 5.0f, 10.0f, 10.0f}) {
        orbit.azimuth_degrees = azimuth;
        const Camera camera = orbit_camera(test::box_center(scene.volume), test::box_radius(scene.volume), orbit);
        const ShadedVolume all =
            shade_voxels(scene.volume, scene.gradients, opacity, scene.colors, scene.lighting, camera);
        EXPECT_TRUE(
            test::same_bytes(renderer.render(camera, settings), composite(all, camera, settings.composite_settings())))
            << "azimuth " << azimuth;
    }
}

// Odd sizes (after VTK's tests): a 127^3 ball seen face on in a 301 x 300 image. No access outside
// the arrays (run under the sanitizers), and the picture is as symmetric as the scene.
TEST(Invariance, OddSizesRenderSymmetricImages) {
    const glm::vec3 center{63.0f};
    const Volume ball = test::ball_volume(glm::ivec3(127), center, 40.0f);
    const GradientField gradients = compute_gradients(ball);
    const Classification translucent = test::piecewise({{50.0f, 0.0f}, {200.0f, 0.3f}});
    const std::vector<float> opacity = classify_voxels(ball, gradients, translucent);
    CompositeSettings settings;
    settings.width = 301;
    settings.height = 300;
    Camera parallel = test::face_on_camera(center, 130.0f);
    Camera perspective = parallel;
    perspective.projection = Projection::Perspective;
    perspective.eye = center - glm::vec3(0.0f, 0.0f, 300.0f);
    perspective.fov_y_degrees = 30.0f;
    for (const Camera& camera : {parallel, perspective}) {
        const ShadedVolume shaded = shade_voxels(ball, gradients, opacity, ColorMap{}, PhongLighting{}, camera);
        const Image image = composite(shaded, camera, settings);
        float largest_alpha = 0.0f;
        for (int y = 0; y < settings.height; ++y) {
            for (int x = 0; x < settings.width; ++x) {
                const glm::vec4 p = image.at(x, y);
                const glm::vec4 mirror_x = image.at(settings.width - 1 - x, y);
                const glm::vec4 mirror_y = image.at(x, settings.height - 1 - y);
                for (int c = 0; c < 4; ++c) {
                    ASSERT_NEAR(p[c], mirror_x[c], 2e-4f) << x << "," << y;
                    ASSERT_NEAR(p[c], mirror_y[c], 2e-4f) << x << "," << y;
                }
                largest_alpha = std::max(largest_alpha, p.a);
            }
        }
        EXPECT_GT(largest_alpha, 0.5f);
        EXPECT_EQ(image.at(0, 0), glm::vec4(0.0f));  // outside the ball
    }
}

}  // namespace
}  // namespace pp5
