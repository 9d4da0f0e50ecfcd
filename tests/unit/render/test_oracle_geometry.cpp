// The reference renderer as the oracle of Levoy's geometry: the region of interest scales the voxels'
// opacities by its factor, capping rewrites the gradients of its transition zone as if the region held
// air, and polygons are scan-converted and matted over the shaded voxels; each checked against what the
// definitions give in closed form.

#include "scene/reference/polygon_matte.h"
#include "scene/reference/reference_renderer.h"
#include "scene/reference/voxel_bricks.h"
#include "scene/reference/voxel_opacity.h"
#include "test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace pp5 {
namespace {

RegionOfInterest cut_box() {
    RegionOfInterest r;
    r.center = glm::vec3(10.0f);
    r.half_size = glm::vec3(4.0f);
    r.scale_inside = 0.0f;
    r.scale_outside = 1.0f;
    r.transition = 2.0f;
    return r;
}

TEST(OracleRegion, OpacitiesAreScaledByTheRegionsFactor) {
    const glm::ivec3 dims(21);
    std::vector<float> opacity(static_cast<std::size_t>(dims.x * dims.y * dims.z), 0.5f);
    const RegionOfInterest region = cut_box();
    scale_by_region(opacity, dims, region);
    const auto at = [&](int x, int y, int z) {
        return opacity[static_cast<std::size_t>(x + dims.x * (y + dims.y * z))];
    };
    EXPECT_FLOAT_EQ(at(10, 10, 10), 0.0f);                                         // inside: cut away
    EXPECT_FLOAT_EQ(at(0, 0, 0), 0.5f);                                            // far outside: kept
    EXPECT_FLOAT_EQ(at(14, 10, 10), 0.5f * region.factor(glm::vec3(14, 10, 10)));  // on the face: halfway
    EXPECT_NEAR(at(14, 10, 10), 0.25f, 1e-6f);
}

TEST(OracleRegion, CappingShadesTheTransitionZoneAsIfTheRegionHeldAir) {
    RegionOfInterest region = cut_box();
    region.cap = true;
    // On the +x face, a flat field of value 100 over air 0: the neighbour towards the region counts as
    // air, so the gradient along the face's outward normal becomes (f - air) / 2.
    const glm::vec3 g = region.capped_gradient(glm::vec3(14.0f, 10.0f, 10.0f), 100.0f, glm::vec3(0.0f), 0.0f);
    EXPECT_NEAR(g.x, 50.0f, 1e-4f);
    EXPECT_NEAR(g.y, 0.0f, 1e-4f);
    EXPECT_NEAR(g.z, 0.0f, 1e-4f);
    // Beyond the band, or without capping, the gradient is the volume's.
    EXPECT_EQ(region.capped_gradient(glm::vec3(17.0f, 10.0f, 10.0f), 100.0f, glm::vec3(1.0f, 2.0f, 3.0f), 0.0f),
              glm::vec3(1.0f, 2.0f, 3.0f));
    region.cap = false;
    EXPECT_EQ(region.capped_gradient(glm::vec3(14.0f, 10.0f, 10.0f), 100.0f, glm::vec3(0.0f), 0.0f), glm::vec3(0.0f));
}

// A region moved from frame to frame caps again in the arrays of the frame before: what that gives is
// what capping into fresh arrays gives, for the gradients and for the bricks the shading reads.
TEST(OracleRegion, CappingAgainInTheLastFramesArraysGivesWhatFreshArraysGive) {
    const Volume volume = test::lumpy_volume(glm::ivec3(21));
    const GradientField gradients = compute_gradients(volume);
    RegionOfInterest first = cut_box(), moved = cut_box();
    first.cap = moved.cap = true;
    moved.center = glm::vec3(8.0f, 12.0f, 9.0f);

    GradientField reused;
    cap_gradients(volume, gradients, first, reused);
    VoxelBricks reused_bricks(volume, reused);
    cap_gradients(volume, gradients, moved, reused);
    reused_bricks.refill(volume, reused);

    GradientField fresh;
    cap_gradients(volume, gradients, moved, fresh);
    const VoxelBricks fresh_bricks(volume, fresh);
    GradientField before_the_move;
    cap_gradients(volume, gradients, first, before_the_move);
    ASSERT_NE(fresh.gradients, before_the_move.gradients);  // the move changed what capping gives
    EXPECT_EQ(reused.gradients, fresh.gradients);
    const std::size_t blocks = OccupancyGrid(volume.dims()).block_count();
    for (std::size_t b = 0; b < blocks; ++b) {
        const auto a = reused_bricks.brick(b), f = fresh_bricks.brick(b);
        ASSERT_TRUE(std::equal(a.begin(), a.end(), f.begin(), f.end())) << "block " << b;
    }
    EXPECT_THROW(reused_bricks.refill(test::lumpy_volume(glm::ivec3(20)), gradients), std::invalid_argument);
}

PolygonSpec square(float z, float side, glm::vec3 color, float opacity) {
    PolygonSpec p;
    p.vertices = {{4.0f, 4.0f, z}, {4.0f + side, 4.0f, z}, {4.0f + side, 4.0f + side, z}, {4.0f, 4.0f + side, z}};
    p.colors = {color};
    p.opacities = {opacity};
    return p;
}

// Voxel `v` of a volume of `dims`, of a uniform blue at opacity 0.5, after the mattes of its block.
glm::vec4 matted_voxel(const PolygonMattes& mattes, glm::ivec3 dims, glm::ivec3 v) {
    ShadedVolume shaded{
        dims, glm::vec3(1.0f),
        std::vector<glm::vec4>(static_cast<std::size_t>(dims.x * dims.y * dims.z), glm::vec4(0.0f, 0.0f, 1.0f, 0.5f))};
    mattes.apply(OccupancyGrid(dims).block_index(v / OccupancyGrid::kBlockSize), shaded);
    return shaded.rgba[static_cast<std::size_t>(v.x + dims.x * (v.y + dims.y * v.z))];
}

TEST(OracleMattes, CoverageSumsToTheAreaAndAFullyCoveredVoxelTakesThePolygon) {
    const glm::ivec3 dims(24);
    // On voxel centres' plane: the sheet holds each covered voxel's every sample point in z.
    const PolygonMattes mattes(dims, {square(10.0f, 12.0f, glm::vec3(1.0f, 0.0f, 0.0f), 1.0f)});
    std::vector<float> opacity(static_cast<std::size_t>(dims.x * dims.y * dims.z), 0.0f);
    mattes.mark_non_empty(opacity);
    const float covered = std::accumulate(opacity.begin(), opacity.end(), 0.0f);
    EXPECT_NEAR(covered, 144.0f, 144.0f * 0.03f);  // the area, one voxel thick

    const glm::vec4 v = matted_voxel(mattes, dims, glm::ivec3(10));
    EXPECT_NEAR(v.r, 1.0f, 1e-5f);
    EXPECT_NEAR(v.b, 0.0f, 1e-5f);
    EXPECT_NEAR(v.a, 1.0f, 1e-5f);
}

TEST(OracleMattes, AHalfTransparentPolygonIsMattedOverTheVoxel) {
    const glm::ivec3 dims(24);
    const PolygonMattes mattes(dims, {square(10.0f, 12.0f, glm::vec3(1.0f, 0.0f, 0.0f), 0.5f)});
    const glm::vec4 v = matted_voxel(mattes, dims, glm::ivec3(10));
    // a = 0.5 + 0.5 x 0.5 = 0.75; c = (red x 0.5 + blue x 0.25) / 0.75.
    EXPECT_NEAR(v.a, 0.75f, 1e-5f);
    EXPECT_NEAR(v.r, 2.0f / 3.0f, 1e-5f);
    EXPECT_NEAR(v.b, 1.0f / 3.0f, 1e-5f);
}

TEST(OracleMattes, ARenderShowsThePolygonInEmptySpace) {
    const Volume volume = test::constant_volume(glm::ivec3(24), 0.0f);
    ReferenceRenderer renderer(volume);
    renderer.set_classification(test::constant_opacity(0.0f), test::constant_color(glm::vec3(0.0f)));
    RenderSettings settings;
    settings.width = settings.height = 32;
    Camera camera;
    camera.eye = glm::vec3(10.0f, 10.0f, 60.0f);
    camera.target = glm::vec3(10.0f, 10.0f, 10.0f);
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.view_height = 30.0f;
    const Image empty = renderer.render(camera, settings);
    renderer.set_polygons({square(10.0f, 12.0f, glm::vec3(1.0f, 0.0f, 0.0f), 1.0f)});
    const Image with = renderer.render(camera, settings);
    EXPECT_LT(empty.at(16, 16).r, 0.01f);  // nothing but the black background
    // The one-voxel sheet, its colour and opacity interpolated with its transparent (black) neighbours.
    EXPECT_GT(with.at(16, 16).r, 0.25f);
    EXPECT_LT(with.at(16, 16).b, 0.01f);
}

}  // namespace
}  // namespace pp5
