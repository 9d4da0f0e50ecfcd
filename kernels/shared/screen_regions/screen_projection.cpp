#include "kernels/shared/screen_regions/screen_projection.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

namespace pp5 {

Quadratic Quadratic::substituted(double sx, double x0, double sy, double y0) const {
    Quadratic q;
    q.a = a * sx * sx;
    q.b = b * sx * sy;
    q.c = c * sy * sy;
    q.d = (2 * a * x0 + b * y0 + d) * sx;
    q.e = (2 * c * y0 + b * x0 + e) * sy;
    q.f = (*this)(x0, y0);
    return q;
}

ScreenProjection::ScreenProjection(const Camera& camera, int width, int height)
    : perspective_(camera.projection == Projection::Perspective), eye_(camera.eye) {
    const ViewBasis basis = view_basis(camera);
    right_ = basis.right;
    up_ = basis.up;
    forward_ = basis.forward;
    principal_ = {width / 2.0 - 0.5, height / 2.0 - 0.5};
    if (perspective_) focal_ = (height / 2.0) / std::tan(glm::radians(static_cast<double>(camera.fov_y_degrees)) / 2.0);
    else pixels_per_unit_ = height / static_cast<double>(camera.view_height);
}

glm::dvec3 ScreenProjection::to_eye(glm::vec3 world) const {
    const glm::dvec3 v = glm::dvec3(world) - eye_;
    return {glm::dot(v, right_), glm::dot(v, up_), glm::dot(v, forward_)};
}

glm::dvec2 ScreenProjection::to_screen(glm::dvec3 e) const {
    const double k = perspective_ ? focal_ / e.z : pixels_per_unit_;
    return {principal_.x + k * e.x, principal_.y - k * e.y};
}

glm::dvec3 ScreenProjection::ray_origin(glm::dvec2 s) const {
    if (perspective_) return eye_;
    return eye_ + ((s.x - principal_.x) * right_ - (s.y - principal_.y) * up_) / pixels_per_unit_;
}

glm::dvec3 ScreenProjection::ray_direction(glm::dvec2 s) const {
    if (!perspective_) return forward_;
    return focal_ * forward_ + (s.x - principal_.x) * right_ - (s.y - principal_.y) * up_;
}

}  // namespace pp5
