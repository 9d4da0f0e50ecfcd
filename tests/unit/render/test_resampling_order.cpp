// Levoy's order (shade and classify the voxels, interpolate colours and opacities) against the other
// (interpolate value and gradient, classify and shade the sample): close on smooth data, different
// where a feature is thinner than a voxel.

#include "scene/reference/reference_renderer.h"
#include "test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pp5 {
namespace {

Image render(const Volume& volume, const Classification& c, ResamplingOrder order, const Camera& camera) {
    ReferenceRenderer renderer(volume);
    renderer.set_classification(c, ColorMap{{{0.0f, {0.8f, 0.6f, 0.5f}}, {200.0f, {1.0f, 1.0f, 1.0f}}}});
    RenderSettings settings;
    settings.width = 64;
    settings.height = 64;
    settings.resampling = order;
    return renderer.render(camera, settings);
}

TEST(ResamplingOrder, AgreeOnSmoothData) {
    // A ball with a soft edge 12 voxels wide: every classification input varies slowly.
    const glm::vec3 center{31.5f};
    const Volume soft = test::make_volume(glm::ivec3(64), glm::vec3(1.0f), [&](int x, int y, int z) {
        const float d = glm::length(glm::vec3(x, y, z) - center);
        return 200.0f * glm::clamp((26.0f - d) / 12.0f, 0.0f, 1.0f);
    });
    const Classification ramp = test::piecewise({{40.0f, 0.0f}, {200.0f, 0.4f}});
    OrbitView view;
    view.azimuth_degrees = 20.0f;
    view.elevation_degrees = 10.0f;
    const Camera camera = orbit_camera(test::box_center(soft), test::box_radius(soft), view);
    const Image pre = render(soft, ramp, ResamplingOrder::ShadeThenInterpolate, camera);
    const Image post = render(soft, ramp, ResamplingOrder::InterpolateThenShade, camera);
    double total = 0.0;
    float largest = 0.0f;
    for (std::size_t i = 0; i < pre.pixels.size(); ++i) {
        for (int c = 0; c < 4; ++c) {
            const float d = std::abs(pre.pixels[i][c] - post.pixels[i][c]);
            total += d;
            largest = std::max(largest, d);
        }
    }
    EXPECT_LT(total / static_cast<double>(4 * pre.pixels.size()), 0.01);
    EXPECT_LT(largest, 0.08f);
}

// A sharp step from 0 to 200 and a thin contour at 100: no voxel is near 100 (the central difference
// there is 100 a voxel, r = 0.4 reaches 40), so Levoy's order sees nothing; interpolated samples cross
// 100 and show the surface.
TEST(ResamplingOrder, ThinContourSeenOnlyWhenClassifyingSamples) {
    const Volume step =
        test::make_volume(glm::ivec3(32), glm::vec3(1.0f), [](int x, int, int) { return x < 16 ? 200.0f : 0.0f; });
    Classification thin;
    thin.kind = ClassificationKind::IsovalueContours;
    thin.contours = {{100.0f, 1.0f, 0.4f}};
    Camera camera = test::face_on_camera(test::box_center(step), 40.0f);
    camera.eye = test::box_center(step) + glm::vec3(100.0f, 0.0f, 0.0f);  // looking along -x at the face
    camera.up = {0.0f, 0.0f, 1.0f};
    const Image pre = render(step, thin, ResamplingOrder::ShadeThenInterpolate, camera);
    const Image post = render(step, thin, ResamplingOrder::InterpolateThenShade, camera);
    float pre_max = 0.0f;
    float post_centre = post.at(32, 32).a;
    for (const glm::vec4& p : pre.pixels) pre_max = std::max(pre_max, p.a);
    EXPECT_EQ(pre_max, 0.0f);
    EXPECT_GT(post_centre, 0.5f);
}

}  // namespace
}  // namespace pp5
