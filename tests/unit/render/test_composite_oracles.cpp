// Analytic oracles for the compositor: scenes whose pixels have closed forms.

#include "scene/reference/composite.h"
#include "scene/reference/post_classified.h"
#include "scene/reference/shaded_volume.h"
#include "scene/reference/voxel_opacity.h"
#include "sim/core/input_error.h"
#include "test_scenes.h"

#include <gtest/gtest.h>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <numbers>

namespace pp5 {
namespace {

using test::constant_volume;

const glm::vec3 kSlabColor{0.2f, 0.5f, 0.9f};
const glm::vec3 kBackground{0.1f, 0.2f, 0.3f};

// A volume of constant opacity alpha and colour kSlabColor, resampled and composited.
Image render_slab(const Volume& volume, float alpha, const Camera& camera, CompositeSettings settings) {
    const GradientField gradients = compute_gradients(volume);
    const std::vector<float> opacity = classify_voxels(volume, gradients, test::constant_opacity(alpha));
    const ShadedVolume shaded =
        shade_voxels(volume, gradients, opacity, test::constant_color(kSlabColor), test::flat_lighting(), camera);
    settings.background = kBackground;
    return composite(shaded, camera, settings);
}

CompositeSettings small_image(float step, bool early_termination = false) {
    CompositeSettings s;
    s.width = 8;
    s.height = 8;
    s.sample_step = step;
    s.early_termination = early_termination;
    return s;
}

void expect_every_pixel(const Image& image, float expected_alpha) {
    for (const glm::vec4& p : image.pixels) {
        ASSERT_NEAR(p.a, expected_alpha, 1e-5f);
        const glm::vec3 expected = kSlabColor * expected_alpha + (1.0f - expected_alpha) * kBackground;
        ASSERT_NEAR(p.r, expected.r, 1e-5f);
        ASSERT_NEAR(p.g, expected.g, 1e-5f);
        ASSERT_NEAR(p.b, expected.b, 1e-5f);
    }
}

// Face on, path length L = 20 voxels: one sample per voxel gives (1 - alpha)^20 transmitted.
TEST(ConstantSlab, TransmittanceAfterTwentyVoxels) {
    const Volume slab = constant_volume({9, 9, 21}, 50.0f);
    const Camera camera = test::face_on_camera({4.0f, 4.0f, 10.0f}, 4.0f);
    const float alpha = 0.1f;
    expect_every_pixel(render_slab(slab, alpha, camera, small_image(1.0f)), 1.0f - std::pow(1.0f - alpha, 20.0f));
    // Half steps: twice the samples, each with opacity 1 - (1 - alpha)^0.5: the same transmittance.
    expect_every_pixel(render_slab(slab, alpha, camera, small_image(0.5f)), 1.0f - std::pow(1.0f - alpha, 20.0f));
}

// A step that does not divide the path: N = floor(L/h + 1/2) samples, transmittance (1-alpha)^(N h),
// within half a step of the continuous (1-alpha)^L.
TEST(ConstantSlab, UnevenStepMatchesDiscreteAndContinuousForms) {
    const Volume slab = constant_volume({9, 9, 21}, 50.0f);
    const Camera camera = test::face_on_camera({4.0f, 4.0f, 10.0f}, 4.0f);
    const float alpha = 0.1f;
    const float step = 0.3f;
    const float samples = std::floor(20.0f / step + 0.5f);
    const Image image = render_slab(slab, alpha, camera, small_image(step));
    expect_every_pixel(image, 1.0f - std::pow(1.0f - alpha, samples * step));
    EXPECT_NEAR(image.pixels[0].a, 1.0f - std::pow(1.0f - alpha, 20.0f), 2e-3f);
}

// Early termination stops at the first sample where A >= 0.95: 1 - 0.9^29 for alpha 0.1.
TEST(ConstantSlab, EarlyTerminationStopsAtTheThreshold) {
    const Volume slab = constant_volume({9, 9, 41}, 50.0f);
    const Camera camera = test::face_on_camera({4.0f, 4.0f, 20.0f}, 4.0f);
    CompositeSettings settings = small_image(1.0f, /*early_termination=*/true);
    settings.termination_opacity = 0.95f;
    expect_every_pixel(render_slab(slab, 0.1f, camera, settings), 1.0f - std::pow(0.9f, 29.0f));
}

// Oblique rays cross the 8-voxel slab along 8 / cos(30 deg) voxels.
TEST(ConstantSlab, ObliquePathLength) {
    const Volume slab = constant_volume({64, 64, 9}, 50.0f);
    Camera camera;
    camera.projection = Projection::Parallel;
    const glm::vec3 center{31.5f, 31.5f, 4.0f};
    const glm::vec3 direction{std::sin(glm::radians(30.0f)), 0.0f, std::cos(glm::radians(30.0f))};
    camera.eye = center - 100.0f * direction;
    camera.target = center;
    camera.view_height = 2.0f;
    const float step = 0.1f;
    const float path = 8.0f / std::cos(glm::radians(30.0f));
    const float samples = std::floor(path / step + 0.5f);
    const Image image = render_slab(slab, 0.1f, camera, small_image(step));
    expect_every_pixel(image, 1.0f - std::pow(0.9f, samples * step));
    EXPECT_NEAR(image.pixels[0].a, 1.0f - std::pow(0.9f, path), 2e-3f);
}

// Anisotropic voxels: steps are measured in the smallest spacing (1 mm), so a 10-voxel, 20 mm deep
// slab takes 20 samples.
TEST(ConstantSlab, StepIsInTheSmallestSpacing) {
    const Volume slab = constant_volume({9, 9, 11}, 50.0f, {1.0f, 1.0f, 2.0f});
    const Camera camera = test::face_on_camera({4.0f, 4.0f, 10.0f}, 4.0f);
    expect_every_pixel(render_slab(slab, 0.1f, camera, small_image(1.0f)), 1.0f - std::pow(0.9f, 20.0f));
}

// The ball's silhouette radius in pixels, from the area where the image is at least half opaque.
float silhouette_radius(const Image& image) {
    int covered = 0;
    for (const glm::vec4& p : image.pixels) covered += p.a >= 0.5f ? 1 : 0;
    return std::sqrt(static_cast<float>(covered) / std::numbers::pi_v<float>);
}

struct BallScene {
    static constexpr int kSize = 64;
    const float radius = 0.35f * kSize;  // 22.4 voxels
    const glm::vec3 center{31.5f};
    const Volume volume = test::ball_volume(glm::ivec3(kSize), center, radius);
    const GradientField gradients = compute_gradients(volume);
    const Classification opaque_inside = test::piecewise({{99.0f, 0.0f}, {101.0f, 1.0f}});
    const ColorMap white{};

    Image render(const Camera& camera, int size) const {
        CompositeSettings s;
        s.width = size;
        s.height = size;
        const std::vector<float> opacity = classify_voxels(volume, gradients, opaque_inside);
        return composite(shade_voxels(volume, gradients, opacity, white, PhongLighting{}, camera), camera, s);
    }
    Image render_post(const Camera& camera, int size) const {
        CompositeSettings s;
        s.width = size;
        s.height = size;
        return render_post_classified(volume, gradients, opaque_inside, white, PhongLighting{}, camera, s);
    }
};

TEST(BallSilhouette, ParallelRadiusMatchesTheBall) {
    const BallScene scene;
    // 48 pixels over 72 voxels: 1.5 voxels a pixel.
    const Camera camera = test::face_on_camera(scene.center, 72.0f);
    const float expected = scene.radius / 1.5f;
    EXPECT_NEAR(silhouette_radius(scene.render(camera, 48)), expected, 1.0f);
    EXPECT_NEAR(silhouette_radius(scene.render_post(camera, 48)), expected, 1.0f);
}

TEST(BallSilhouette, PerspectiveRadiusMatchesTheProjectedCone) {
    const BallScene scene;
    Camera camera;
    camera.projection = Projection::Perspective;
    const float distance = 80.0f;
    camera.eye = scene.center - glm::vec3(0.0f, 0.0f, distance);
    camera.target = scene.center;
    camera.fov_y_degrees = 40.0f;
    const int size = 48;
    // Silhouette cone half-angle asin(R/D); on the image plane tan of it, in pixels.
    const float focal_pixels = 0.5f * static_cast<float>(size) / std::tan(glm::radians(20.0f));
    const float expected = focal_pixels * scene.radius / std::sqrt(distance * distance - scene.radius * scene.radius);
    EXPECT_NEAR(silhouette_radius(scene.render(camera, size)), expected, 1.0f);
    EXPECT_NEAR(silhouette_radius(scene.render_post(camera, size)), expected, 1.0f);
}

TEST(Composite, RaysThatMissShowTheBackground) {
    const Volume slab = constant_volume({9, 9, 9}, 50.0f);
    Camera away = test::face_on_camera({4.0f, 4.0f, 4.0f}, 4.0f);
    away.eye = {4.0f, 4.0f, 20.0f};  // beyond the volume, looking further away
    away.target = {4.0f, 4.0f, 40.0f};
    CompositeStats stats;
    const GradientField gradients = compute_gradients(slab);
    const std::vector<float> opacity = classify_voxels(slab, gradients, test::constant_opacity(0.5f));
    CompositeSettings settings = small_image(1.0f);
    settings.background = kBackground;
    const Image image =
        composite(shade_voxels(slab, gradients, opacity, ColorMap{}, PhongLighting{}, away), away, settings, &stats);
    for (const glm::vec4& p : image.pixels) EXPECT_EQ(p, glm::vec4(kBackground, 0.0f));
    EXPECT_EQ(stats.rays, 64u);
    EXPECT_EQ(stats.rays_hit, 0u);
}

TEST(Composite, FlatVolumeHasNoInteriorAndRendersBackground) {
    const Volume sheet = constant_volume({9, 9, 1}, 50.0f);
    const Camera camera = test::face_on_camera({4.0f, 4.0f, 0.0f}, 4.0f);
    const GradientField gradients = compute_gradients(sheet);
    const std::vector<float> opacity = classify_voxels(sheet, gradients, test::constant_opacity(0.5f));
    const Image image = composite(shade_voxels(sheet, gradients, opacity, ColorMap{}, PhongLighting{}, camera), camera,
                                  small_image(1.0f));
    for (const glm::vec4& p : image.pixels) EXPECT_EQ(p, glm::vec4(0.0f));
}

TEST(Composite, CameraInsideTheVolumeSamplesFromTheEye) {
    const Volume slab = constant_volume({9, 9, 41}, 50.0f);
    Camera inside = test::face_on_camera({4.0f, 4.0f, 20.0f}, 4.0f);
    inside.projection = Projection::Perspective;
    inside.eye = {4.0f, 4.0f, 30.0f};  // 10 voxels before the far face, looking at it
    inside.target = {4.0f, 4.0f, 40.0f};
    inside.fov_y_degrees = 1.0f;
    const Image image = render_slab(slab, 0.1f, inside, small_image(1.0f));
    EXPECT_NEAR(image.at(4, 4).a, 1.0f - std::pow(0.9f, 10.0f), 1e-3f);
}

TEST(Composite, RejectsBadSettings) {
    const Volume slab = constant_volume({9, 9, 9}, 50.0f);
    const GradientField gradients = compute_gradients(slab);
    const std::vector<float> opacity = classify_voxels(slab, gradients, test::constant_opacity(0.5f));
    const Camera camera = test::face_on_camera({4.0f, 4.0f, 4.0f}, 4.0f);
    const ShadedVolume shaded = shade_voxels(slab, gradients, opacity, ColorMap{}, PhongLighting{}, camera);
    CompositeSettings bad = small_image(0.0f);
    EXPECT_THROW(composite(shaded, camera, bad), InputError);
    bad = small_image(1.0f);
    bad.termination_opacity = 1.5f;
    EXPECT_THROW(composite(shaded, camera, bad), InputError);
    bad = small_image(1.0f);
    bad.width = 0;
    EXPECT_THROW(composite(shaded, camera, bad), InputError);
}

}  // namespace
}  // namespace pp5
