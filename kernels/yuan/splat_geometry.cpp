#include "kernels/yuan/splat_geometry.h"

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

std::optional<SplatShape> project_sphere(const ScreenProjection& projection, glm::dvec3 c, double radius) {
    SplatShape shape;
    shape.projected_center = projection.to_screen(c);
    if (!projection.perspective()) {
        // A circle of radius r k about the projected centre: inside = 1 - |p - centre|^2 / R^2, scaled by R^2.
        const double r = radius * projection.pixels_per_unit(c.z);
        const glm::dvec2 p = shape.projected_center;
        shape.inside = Quadratic{-1, 0, -1, 2 * p.x, 2 * p.y, r * r - p.x * p.x - p.y * p.y};
        shape.center = p;
        shape.half_extent = {r, r};
        shape.peak = r * r;
        return shape;
    }
    const double length = glm::length(c);
    // The cone closes in front of the eye only if the sphere clears the eye's plane.
    if (c.z <= radius * 1.0001 || length <= radius * 1.0001) return std::nullopt;
    const glm::dvec3 q = c / length;
    const double sin2 = (radius / length) * (radius / length);
    const double cos2 = 1 - sin2;
    const double f = projection.focal_pixels();
    // E in (u, v), the offsets from the principal point with v up; then in screen coordinates.
    const Quadratic in_view{q.x * q.x - cos2, 2 * q.x * q.y, q.y * q.y - cos2, 2 * f * q.x * q.z, 2 * f * q.y * q.z,
                            f * f * (q.z * q.z - cos2)};
    const glm::dvec2 pp = projection.principal_point();
    shape.inside = in_view.substituted(1, -pp.x, -1, pp.y);
    const Quadratic& e = shape.inside;
    // The ellipse's centre is where the gradient vanishes; its box from the inverse of the form.
    const double det = 4 * e.a * e.c - e.b * e.b;  // > 0 for an ellipse
    if (!(det > 0)) return std::nullopt;
    shape.center = {(e.b * e.e - 2 * e.c * e.d) / det, (e.b * e.d - 2 * e.a * e.e) / det};
    shape.peak = e(shape.center.x, shape.center.y);
    if (!(shape.peak > 0)) return std::nullopt;
    // inside(center + d) = peak + d' M d with M = [[a, b/2], [b/2, c]] negative definite.
    const double quarter_det = det / 4;  // det(M)
    shape.half_extent = {std::sqrt(shape.peak * -e.c / quarter_det), std::sqrt(shape.peak * -e.a / quarter_det)};
    shape.sin_alpha = std::sqrt(sin2);
    shape.cos2_alpha = cos2;
    shape.axis = q;
    return shape;
}

EllipseClosedForm ellipse_closed_form(double rho, double alpha, double f) {
    EllipseClosedForm e;
    const double big_d = std::cos(rho) * std::cos(rho) - std::sin(alpha) * std::sin(alpha);
    e.near_edge = f * std::tan(rho - alpha);
    e.far_edge = f * std::tan(rho + alpha);
    e.center = f * std::sin(rho) * std::cos(rho) / big_d;
    e.radial_semi_axis = f * std::sin(alpha) * std::cos(alpha) / big_d;
    e.tangential_semi_axis = f * std::sin(alpha) / std::sqrt(big_d);
    return e;
}

double corrected_index_squared(double i2, double sin_alpha) {
    const double s2 = sin_alpha * sin_alpha;
    return i2 / ((1 - s2) + i2 * s2);
}

double exact_index_squared(const ScreenProjection& projection, const SplatShape& shape, glm::dvec2 screen) {
    const glm::dvec2 pp = projection.principal_point();
    const glm::dvec3 x{screen.x - pp.x, pp.y - screen.y, projection.focal_pixels()};
    const double x2 = glm::dot(x, x);
    const double along = glm::dot(x, shape.axis);
    return (x2 - along * along) / (x2 * shape.sin_alpha * shape.sin_alpha);
}

}  // namespace pp5
