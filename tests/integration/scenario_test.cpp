// The scenario files under traces/ and the scenario format's rules.

#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"
#include "tests/support/source_dir.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

fs::path shipped(const std::string& name) { return pp5::test::source_dir() / "traces/scenarios" / name; }

fs::path write_scenario(const std::string& name, const std::string& text) {
    const fs::path path = fs::temp_directory_path() / ("pp5_scenario_test_" + name + ".toml");
    std::ofstream(path) << text;
    return path;
}

TEST(Scenario, EveryShippedScenarioLoads) {
    for (const auto& entry : fs::directory_iterator(pp5::test::source_dir() / "traces/scenarios")) {
        if (entry.path().extension() != ".toml") continue;
        EXPECT_NO_THROW(load_scenario(entry.path())) << entry.path();
    }
}

TEST(Scenario, DefaultDemoIsTheMrHead) {
    const Scenario s = load_scenario(shipped("mr-head.toml"));
    EXPECT_EQ(s.dataset.source, DatasetSpec::Source::Packaged);
    EXPECT_EQ(s.dataset.name, "ch2");
    EXPECT_EQ(s.image.width, 512);
    EXPECT_EQ(s.image.height, 512);
    ASSERT_EQ(s.frames.size(), 1u);
    EXPECT_EQ(s.frames[0].classification.kind, ClassificationKind::IsovalueContours);
}

TEST(Scenario, FramesPatchThePreviousFrame) {
    const Scenario s = load_scenario(shipped("head-phantom.toml"));
    ASSERT_EQ(s.frames.size(), 4u);
    EXPECT_FLOAT_EQ(s.frames[1].camera.azimuth_degrees, 30.0f);
    EXPECT_FLOAT_EQ(s.frames[2].camera.azimuth_degrees, 30.0f);  // kept from the frame before
    EXPECT_FALSE(s.frames[2].lighting.light_follows_camera);
    EXPECT_FALSE(s.frames[3].lighting.light_follows_camera);  // kept
    EXPECT_EQ(s.frames[2].classification.contours.size(), 2u);
    EXPECT_EQ(s.frames[3].classification.contours.size(), 1u);
    EXPECT_TRUE(s.frames[1].camera_changed);
    EXPECT_FALSE(s.frames[1].lighting_changed);
    EXPECT_FALSE(s.frames[2].camera_changed);
    EXPECT_TRUE(s.frames[3].classification_changed);
}

TEST(Scenario, OrbitCameraLooksAtTheCentreFromItsDistance) {
    CameraSpec spec;
    spec.view_from = {0, 1, 0};
    spec.up = {0, 0, 1};
    spec.distance = 4.0f;
    spec.zoom = 2.0f;
    const glm::vec3 center{10, 20, 30};
    Camera c = spec.camera_for(center, 5.0f);
    EXPECT_NEAR(glm::length(c.eye - center), 20.0f, 1e-4f);
    EXPECT_NEAR(c.eye.y - center.y, 20.0f, 1e-4f);
    EXPECT_FLOAT_EQ(c.view_height, 5.0f);
    spec.azimuth_degrees = 90.0f;
    c = spec.camera_for(center, 5.0f);
    EXPECT_NEAR(std::abs(c.eye.x - center.x), 20.0f, 1e-3f);  // turned a quarter about up
    EXPECT_NEAR(c.eye.z, center.z, 1e-3f);
    spec.elevation_degrees = 30.0f;
    c = spec.camera_for(center, 5.0f);
    EXPECT_NEAR(c.eye.z - center.z, 20.0f * 0.5f, 1e-3f);
}

// Each case must fail with an InputError naming this file and the given field.
void expect_bad(const std::string& name, const std::string& text, const std::string& field) {
    const fs::path path = write_scenario(name, text);
    try {
        load_scenario(path);
        ADD_FAILURE() << name << ": accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), path.string()) << name;
        EXPECT_EQ(e.field(), field) << name << ": " << e.what();
    }
}

TEST(Scenario, MalformedFilesNameTheField) {
    const std::string ok = "[dataset]\nphantom = \"sphere\"\n[classification]\ncontours = [{ value = 100 }]\n";
    expect_bad("no_dataset", "[classification]\ncontours = [{ value = 1 }]\n", "dataset");
    expect_bad("two_sources",
               "[dataset]\nphantom = \"sphere\"\npackaged = \"ch2\"\n[classification]\ncontours = [{ value = 1 }]\n",
               "dataset");
    expect_bad("unknown_package", "[dataset]\npackaged = \"nope\"\n[classification]\ncontours = [{ value = 1 }]\n",
               "dataset.packaged");
    expect_bad("unknown_key", ok + "[image]\nwidht = 3\n", "image.widht");
    expect_bad("zero_width", ok + "[image]\nwidth = 0\n", "image.width");
    expect_bad("nan_step", ok + "[image]\nsample_step = nan\n", "image.sample_step");
    expect_bad("bad_projection", ok + "[camera]\nprojection = \"fisheye\"\n", "camera.projection");
    expect_bad("up_parallel", ok + "[camera]\nview_from = [0, 0, 1]\n", "camera.up");
    expect_bad("opacity_range",
               "[dataset]\nphantom = \"sphere\"\n[classification]\ncontours = [{ value = 1, opacity = 2 }]\n",
               "classification.contours[0].opacity");
    expect_bad("unsorted_points",
               "[dataset]\nphantom = \"sphere\"\n[classification]\nkind = \"piecewise-linear\"\n"
               "points = [{ value = 5, opacity = 0 }, { value = 1, opacity = 1 }]\n",
               "classification.points[1].value");
    expect_bad("few_points",
               "[dataset]\nphantom = \"sphere\"\n[classification]\nkind = \"region-boundaries\"\n"
               "points = [{ value = 5, opacity = 0 }]\n",
               "classification.points");
    expect_bad("bad_frame_key", ok + "[[frames]]\ncamera = { azimuth = 3, spin = 1 }\n", "frames[0].camera.spin");
    expect_bad(
        "raw_without_type",
        "[dataset]\nfile = \"x.raw\"\nraw = { dims = [2, 2, 2] }\n[classification]\ncontours = [{ value = 1 }]\n",
        "dataset.raw.type");
    expect_bad("depth_cue", ok + "[shading]\ndepth_cue = [0, 1]\n", "shading.depth_cue");
    expect_bad("stationary_no_direction", ok + "[shading]\nstationary_lights = [{ intensity = 0.5 }]\n",
               "shading.stationary_lights[0].direction");
    expect_bad("stationary_zero",
               ok + "[shading]\nstationary_lights = [{ direction = [1, 0, 0] }, { direction = [0, 0, 0] }]\n",
               "shading.stationary_lights[1].direction");
    expect_bad("stationary_dark", ok + "[shading]\nstationary_lights = [{ direction = [1, 0, 0], intensity = -1 }]\n",
               "shading.stationary_lights[0].intensity");
    std::string nine = "stationary_lights = [";
    for (int i = 0; i < 9; ++i)
        nine += std::string(i == 0 ? "" : ", ") + "{ direction = [1, " + std::to_string(i) + ", 0] }";
    expect_bad("stationary_many", ok + "[shading]\n" + nine + "]\n", "shading.stationary_lights");
}

TEST(Scenario, StationaryLightsAreReadAndKeptByLaterFrames) {
    const std::string text =
        "[dataset]\nphantom = \"sphere\"\n[classification]\ncontours = [{ value = 100 }]\n"
        "[shading]\nlight_direction = [0, 0, -1]\nstationary_lights = [{ direction = [-2, 0, 0], intensity = 0.5 }, "
        "{ direction = [0, 1, 0] }]\n"
        "[[frames]]\n[[frames]]\nshading = { light_direction = [1, 0, -1] }\n";
    const Scenario s = load_scenario_text(text, "stationary.toml");
    ASSERT_EQ(s.frames.size(), 2u);
    for (const FrameSpec& f : s.frames) {
        ASSERT_EQ(f.lighting.stationary_lights.size(), 2u);
        EXPECT_EQ(f.lighting.stationary_lights[0].direction, glm::vec3(-1.0f, 0.0f, 0.0f));  // normalised
        EXPECT_FLOAT_EQ(f.lighting.stationary_lights[0].intensity, 0.5f);
        EXPECT_FLOAT_EQ(f.lighting.stationary_lights[1].intensity, 1.0f);
    }
    EXPECT_TRUE(s.frames[1].lighting_changed);
    EXPECT_NE(s.frames[1].lighting.light_direction, s.frames[0].lighting.light_direction);
}

TEST(Scenario, GeometryAndRegionAreRead) {
    const Scenario s = load_scenario(shipped("ct-head-region.toml"));
    EXPECT_EQ(s.polygons.size(), 20u + 24u);  // the icosahedron's and the beam's triangles
    ASSERT_TRUE(s.frames[0].region.has_value());
    EXPECT_EQ(s.frames[0].region->shape, RegionOfInterest::Shape::Box);
    EXPECT_FLOAT_EQ(s.frames[0].region->scale_inside, 0.02f);
    EXPECT_FLOAT_EQ(s.frames[1].region->center.x, 155.0f);
    EXPECT_FLOAT_EQ(s.frames[1].region->half_size.x, 22.0f);  // kept from the frame before
    EXPECT_TRUE(s.frames[1].region_changed);
    const Scenario f5 = load_scenario(shipped("ct-head-polygons.toml"));
    ASSERT_EQ(f5.polygons.size(), 3u);
    EXPECT_EQ(f5.polygons[0].vertices.size(), 4u);
    EXPECT_FALSE(f5.frames[0].region.has_value());
}

TEST(Scenario, BadGeometryNamesTheFieldOrFile) {
    const std::string ok = "[dataset]\nphantom = \"sphere\"\n[classification]\ncontours = [{ value = 100 }]\n";
    expect_bad("nan_vertex", ok + "[[polygons]]\nvertices = [[0, 0, 0], [1, nan, 0], [0, 1, 0]]\n",
               "polygons[0].vertices");
    expect_bad("two_vertices", ok + "[[polygons]]\nvertices = [[0, 0, 0], [1, 0, 0]]\n", "polygons[0].vertices");
    expect_bad("bad_colour", ok + "[[polygons]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\ncolor = [2, 0, 0]\n",
               "polygons[0].color");
    expect_bad("missing_obj", ok + "[[meshes]]\nfile = \"no-such-mesh.obj\"\n", "meshes[0].file");
    const fs::path empty = fs::temp_directory_path() / "pp5_empty_mesh.obj";
    std::ofstream(empty) << "# nothing here\nv 0 0 0\n";
    expect_bad("empty_mesh", ok + "[[meshes]]\nfile = \"" + empty.string() + "\"\n", "meshes[0].file");
    // An index too large for an int, which tinyobj would read as some other vertex.
    const fs::path huge_index = fs::temp_directory_path() / "pp5_huge_index_mesh.obj";
    std::ofstream(huge_index) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n";
    expect_bad("huge_index", ok + "[[meshes]]\nfile = \"" + huge_index.string() + "\"\n", "meshes[0].file");
    // A mesh path that loops back on itself is unreadable, not an internal error.
    const fs::path loop = fs::temp_directory_path() / "pp5_loop_mesh.obj";
    fs::remove(loop);
    fs::create_symlink(loop, loop);
    expect_bad("looping_mesh", ok + "[[meshes]]\nfile = \"" + loop.string() + "\"\n", "meshes[0].file");
    expect_bad("far_vertex", ok + "[[polygons]]\nvertices = [[0, 0, 0], [1e30, 0, 0], [0, 1, 0]]\n",
               "polygons[0].vertices");
    expect_bad("bad_region", ok + "[region]\nhalf_size = [0, 1, 1]\n", "region.half_size");
    expect_bad("bad_region_shape", ok + "[region]\nshape = \"torus\"\n", "region.shape");
    expect_bad("hairline_ramp", ok + "[region]\ntransition = 1e-30\n",
               "region.transition");  // its slope would not fit the PPs
    expect_bad("capped_ellipsoid", ok + "[region]\nshape = \"ellipsoid\"\ncap = true\n", "region.cap");
    expect_bad("capped_hard_edge", ok + "[region]\ntransition = 0\ncap = true\n", "region.cap");
    expect_bad("dot_dot_name", "[scenario]\nname = \"..\"\n" + ok, "scenario.name");
}

}  // namespace
}  // namespace pp5
