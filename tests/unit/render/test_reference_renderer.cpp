// The stage cache: each stage is recomputed exactly when its inputs change (Levoy, "Optimization for
// animation sequences"), and the cached result is the one the stage functions give.

#include "scene/reference/post_classified.h"
#include "scene/reference/reference_renderer.h"
#include "sim/core/input_error.h"
#include "test_scenes.h"

#include <gtest/gtest.h>

namespace pp5 {
namespace {

struct Stages {
    bool gradients, opacities, colours;
    bool operator==(const Stages&) const = default;
};

std::ostream& operator<<(std::ostream& os, const Stages& s) {
    return os << "{gradients " << s.gradients << ", opacities " << s.opacities << ", colours " << s.colours << "}";
}

class RendererCache : public ::testing::Test {
protected:
    const Volume volume = test::lumpy_volume({41, 37, 33});
    ReferenceRenderer renderer{volume};
    RenderSettings settings;
    OrbitView orbit;

    void SetUp() override {
        settings.width = 40;
        settings.height = 36;
        renderer.set_classification(test::piecewise({{20.0f, 0.0f}, {150.0f, 0.8f}}), ColorMap{});
    }
    Camera camera() const { return orbit_camera(test::box_center(volume), test::box_radius(volume), orbit); }
    Stages render(const Camera& c) {
        RenderStats stats;
        renderer.render(c, settings, &stats);
        last = stats;
        return {stats.gradients_computed, stats.opacities_computed, stats.colours_computed};
    }
    RenderStats last;
};

TEST_F(RendererCache, RecomputesOnlyWhatChanged) {
    EXPECT_EQ(render(camera()), (Stages{true, true, true}));
    EXPECT_GT(last.voxels_shaded, 0u);
    EXPECT_EQ(render(camera()), (Stages{false, false, false}));  // the same frame again
    EXPECT_EQ(last.voxels_shaded, 0u);

    orbit.azimuth_degrees = 5.0f;  // the camera moves: colours only
    EXPECT_EQ(render(camera()), (Stages{false, false, true}));
    EXPECT_GT(last.voxels_shaded, 0u);

    PhongLighting dimmer;
    dimmer.diffuse = 0.5f;
    renderer.set_lighting(dimmer);
    EXPECT_EQ(render(camera()), (Stages{false, false, true}));

    renderer.set_classification(renderer.classification(), ColorMap{{{0.0f, {1.0f, 0.0f, 0.0f}}}});  // colours only
    EXPECT_EQ(render(camera()), (Stages{false, false, true}));

    renderer.set_classification(test::piecewise({{30.0f, 0.0f}, {150.0f, 0.8f}}), renderer.color_map());
    EXPECT_EQ(render(camera()), (Stages{false, true, true}));

    renderer.set_lighting(dimmer);  // unchanged settings: nothing to do
    EXPECT_EQ(render(camera()), (Stages{false, false, false}));
}

TEST_F(RendererCache, ZoomAndImageSizeDoNotReshade) {
    orbit.projection = Projection::Parallel;
    render(camera());
    orbit.zoom = 1.7f;
    settings.width = 50;
    EXPECT_EQ(render(camera()), (Stages{false, false, false}));
}

TEST_F(RendererCache, HeldColoursSurviveCameraMotion) {
    settings.hold_colours_when_camera_moves = true;
    render(camera());
    orbit.azimuth_degrees = 40.0f;
    EXPECT_EQ(render(camera()), (Stages{false, false, false}));
    settings.hold_colours_when_camera_moves = false;
    EXPECT_EQ(render(camera()), (Stages{false, false, true}));
}

TEST_F(RendererCache, InterpolateThenShadeMatchesTheStageFunction) {
    settings.resampling = ResamplingOrder::InterpolateThenShade;
    const Camera c = camera();
    const Image cached = renderer.render(c, settings);
    const Image direct =
        render_post_classified(volume, compute_gradients(volume), renderer.classification(), renderer.color_map(),
                               renderer.lighting(), c, settings.composite_settings());
    EXPECT_TRUE(test::same_bytes(cached, direct));
}

TEST_F(RendererCache, RejectsBadInput) {
    EXPECT_THROW(renderer.set_classification(test::piecewise({{5.0f, 0.0f}, {1.0f, 1.0f}}), ColorMap{}), InputError);
    PhongLighting bad;
    bad.ambient = -1.0f;
    EXPECT_THROW(renderer.set_lighting(bad), InputError);
    settings.sample_step = -1.0f;
    EXPECT_THROW(renderer.render(camera(), settings), InputError);
}

}  // namespace
}  // namespace pp5
