#include "kernels/yuan/splat_geometry.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

namespace pp5 {

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
    const Quadratic in_view{q.x * q.x - cos2,  2 * q.x * q.y,     q.y * q.y - cos2,
                            2 * f * q.x * q.z, 2 * f * q.y * q.z, f * f * (q.z * q.z - cos2)};
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
