#include "scene/render/camera.h"

#include "sim/core/input_error.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <string>

namespace pp5 {

namespace {

bool is_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

glm::vec3 Camera::forward() const { return glm::normalize(target - eye); }

Ray Camera::ray_for_pixel(int px, int py, int width, int height) const {
    return PixelRays(*this, width, height).ray(px, py);
}

void validate_camera(const Camera& camera) {
    if (!is_finite(camera.eye)) reject_field("camera.eye", "must be finite");
    if (!is_finite(camera.target)) reject_field("camera.target", "must be finite");
    if (!is_finite(camera.up)) reject_field("camera.up", "must be finite");
    const glm::vec3 view = camera.target - camera.eye;
    if (glm::length(view) <= 0.0f) reject_field("camera.target", "must differ from camera.eye");
    const glm::vec3 side = glm::cross(glm::normalize(view), camera.up);
    // Up within ~0.06 degrees of the view direction leaves the image's orientation undefined.
    if (!(glm::length(side) > 1e-6f * glm::length(camera.up)))
        reject_field("camera.up", "must not be parallel to the view direction");
    if (camera.projection == Projection::Perspective &&
        !(camera.fov_y_degrees > 0.0f && camera.fov_y_degrees < 180.0f)) {
        reject_field("camera.fov_y_degrees", "must lie in (0, 180)");
    }
    if (camera.projection == Projection::Parallel &&
        !(camera.view_height > 0.0f && std::isfinite(camera.view_height))) {
        reject_field("camera.view_height", "must be positive");
    }
}

ViewBasis view_basis(const Camera& camera) {
    ViewBasis basis{};
    basis.forward = camera.forward();
    basis.right = glm::normalize(glm::cross(basis.forward, camera.up));
    basis.up = glm::cross(basis.right, basis.forward);
    return basis;
}

PixelRays::PixelRays(const Camera& camera, int width, int height)
    : projection_(camera.projection),
      eye_(camera.eye),
      basis_(view_basis(camera)),
      half_width_(0.5f * static_cast<float>(width)),
      half_height_(0.5f * static_cast<float>(height)) {
    const float rows = static_cast<float>(height);
    if (projection_ == Projection::Parallel) {
        pixel_size_ = camera.view_height / rows;
    } else {
        // The image plane at unit distance spans 2 tan(fov/2) vertically.
        pixel_size_ = 2.0f * std::tan(0.5f * glm::radians(camera.fov_y_degrees)) / rows;
    }
}

Camera orbit_camera(glm::vec3 center, float radius, const OrbitView& view) {
    if (!(radius > 0.0f && std::isfinite(radius))) reject_field("orbit.radius", "must be positive");
    if (!(view.distance_factor > 1.0f && std::isfinite(view.distance_factor))) {
        reject_field("orbit.distance_factor", "must exceed 1 (the eye outside the bounding sphere)");
    }
    if (!(view.zoom > 0.0f && std::isfinite(view.zoom))) reject_field("orbit.zoom", "must be positive");

    const float azimuth = glm::radians(view.azimuth_degrees);
    const float elevation = glm::radians(view.elevation_degrees);
    const glm::vec3 world_up{0.0f, 0.0f, 1.0f};
    const glm::vec3 horizontal{std::sin(azimuth), -std::cos(azimuth), 0.0f};  // centre -> eye, on the ground
    const glm::vec3 to_eye = std::cos(elevation) * horizontal + std::sin(elevation) * world_up;

    Camera camera;
    camera.projection = view.projection;
    camera.target = center;
    camera.eye = center + view.distance_factor * radius * to_eye;
    // The derivative of the eye's position with elevation: perpendicular to the view even at the poles.
    camera.up = -std::sin(elevation) * horizontal + std::cos(elevation) * world_up;
    camera.view_height = 2.0f * radius / view.zoom;
    // The bounding sphere's silhouette cone has half-angle asin(1 / distance_factor).
    const float half_angle = std::asin(1.0f / view.distance_factor);
    camera.fov_y_degrees = 2.0f * glm::degrees(std::atan(std::tan(half_angle) / view.zoom));
    return camera;
}

}  // namespace pp5
