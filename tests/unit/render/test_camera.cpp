#include "scene/render/camera.h"
#include "sim/core/input_error.h"
#include "tests/support/vector_expectations.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

namespace pp5 {
namespace {

using test::expect_near;

Camera looking_along_z(Projection projection) {
    Camera c;
    c.projection = projection;
    c.eye = {0.0f, 0.0f, -10.0f};
    c.target = {0.0f, 0.0f, 0.0f};
    c.up = {0.0f, 1.0f, 0.0f};
    c.view_height = 4.0f;
    c.fov_y_degrees = 60.0f;
    return c;
}

TEST(Camera, BasisIsOrthonormalAndRightHanded) {
    const ViewBasis b = view_basis(looking_along_z(Projection::Parallel));
    expect_near(b.forward, {0, 0, 1});
    expect_near(b.up, {0, 1, 0});
    expect_near(b.right, glm::cross(b.forward, b.up));  // looking along +z with +y up, right is -x
    expect_near(b.right, {-1, 0, 0});
}

TEST(Camera, ParallelRaysAreSquarePixelsAboutTheEye) {
    const Camera c = looking_along_z(Projection::Parallel);
    // 5 x 4 image, view height 4: pixels of 1 unit.
    for (int py = 0; py < 4; ++py) {
        for (int px = 0; px < 5; ++px) {
            const Ray r = c.ray_for_pixel(px, py, 5, 4);
            expect_near(r.direction, {0, 0, 1});
            const float right = static_cast<float>(px) + 0.5f - 2.5f;
            const float up = 2.0f - (static_cast<float>(py) + 0.5f);
            expect_near(r.origin, glm::vec3(-right, up, -10.0f));
        }
    }
    expect_near(c.ray_for_pixel(2, 0, 5, 5).origin, {0.0f, 1.6f, -10.0f});  // odd size: a centre column
}

TEST(Camera, PerspectiveRaysStartAtTheEyeAndSpanTheFieldOfView) {
    const Camera c = looking_along_z(Projection::Perspective);
    const Ray centre = c.ray_for_pixel(50, 50, 101, 101);
    expect_near(centre.origin, c.eye);
    expect_near(centre.direction, {0, 0, 1});
    // The top row's centre is half a pixel inside the top edge of the 60 degree field.
    const int height = 100;
    const Ray top = c.ray_for_pixel(0, 0, 1, height);
    const float half_height = std::tan(glm::radians(30.0f));
    const float expected = std::atan(half_height * (1.0f - 1.0f / static_cast<float>(height)));
    EXPECT_NEAR(std::atan2(top.direction.y, top.direction.z), expected, 1e-5f);
    EXPECT_NEAR(glm::length(top.direction), 1.0f, 1e-6f);
}

TEST(Camera, PixelRaysMatchRayForPixel) {
    Camera c = looking_along_z(Projection::Perspective);
    c.eye = {3.0f, -2.0f, 7.0f};
    c.up = {0.3f, 0.1f, 1.0f};
    const PixelRays rays(c, 17, 9);
    for (int py = 0; py < 9; ++py) {
        for (int px = 0; px < 17; ++px) {
            const Ray a = rays.ray(px, py);
            const Ray b = c.ray_for_pixel(px, py, 17, 9);
            EXPECT_EQ(a.origin, b.origin);
            EXPECT_EQ(a.direction, b.direction);
        }
    }
}

TEST(Camera, ValidationNamesTheBadField) {
    Camera c = looking_along_z(Projection::Perspective);
    EXPECT_NO_THROW(validate_camera(c));
    Camera same = c;
    same.target = same.eye;
    EXPECT_THROW(validate_camera(same), InputError);
    Camera parallel_up = c;
    parallel_up.up = {0.0f, 0.0f, 2.0f};
    try {
        validate_camera(parallel_up);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "camera.up");
    }
    Camera fov = c;
    fov.fov_y_degrees = 180.0f;
    EXPECT_THROW(validate_camera(fov), InputError);
    Camera flat = looking_along_z(Projection::Parallel);
    flat.view_height = 0.0f;
    EXPECT_THROW(validate_camera(flat), InputError);
}

TEST(OrbitCamera, LooksAtTheCentreFromTheRequestedSide) {
    const glm::vec3 center{10.0f, 20.0f, 30.0f};
    OrbitView view;
    view.distance_factor = 4.0f;
    Camera front = orbit_camera(center, 5.0f, view);
    expect_near(front.eye, center + glm::vec3(0.0f, -20.0f, 0.0f), 1e-4f);
    expect_near(front.up, {0, 0, 1});
    EXPECT_EQ(front.target, center);
    view.azimuth_degrees = 90.0f;
    expect_near(orbit_camera(center, 5.0f, view).eye, center + glm::vec3(20.0f, 0.0f, 0.0f), 1e-4f);
    view.azimuth_degrees = 0.0f;
    view.elevation_degrees = 90.0f;  // straight down: still a valid frame
    const Camera top = orbit_camera(center, 5.0f, view);
    expect_near(top.eye, center + glm::vec3(0.0f, 0.0f, 20.0f), 1e-4f);
    EXPECT_NO_THROW(validate_camera(top));
}

TEST(OrbitCamera, FramesTheBoundingSphere) {
    OrbitView view;
    view.distance_factor = 2.0f;  // sphere's half-angle 30 degrees
    view.projection = Projection::Perspective;
    EXPECT_NEAR(orbit_camera({}, 1.0f, view).fov_y_degrees, 60.0f, 1e-3f);
    view.zoom = 2.0f;
    EXPECT_NEAR(std::tan(glm::radians(orbit_camera({}, 1.0f, view).fov_y_degrees / 2.0f)),
                std::tan(glm::radians(30.0f)) / 2.0f, 1e-5f);
    view.projection = Projection::Parallel;
    EXPECT_NEAR(orbit_camera({}, 3.0f, view).view_height, 3.0f, 1e-6f);  // 2r / zoom
    view.distance_factor = 1.0f;
    EXPECT_THROW(orbit_camera({}, 1.0f, view), InputError);
}

}  // namespace
}  // namespace pp5
