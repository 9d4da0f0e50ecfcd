#pragma once
// Where a voxel lands on the screen, and the exact shape of a spherical kernel's projection.
//
// Screen coordinates are pixel indices: pixel (i, j)'s centre is (i, j), j down from the top row.
// Under a perspective camera the eye rays tangent to a sphere form a cone, and the splat is where the
// cone meets the image plane: with X the ray through a screen point (in pixels, the image plane at
// distance f), Q the unit direction to the sphere's centre and alpha the cone's half angle, the point
// is inside when E(X) = (X.Q)^2 - cos^2(alpha) |X|^2 > 0. That is one quadratic of the screen position,
// which the renderers' QEE evaluates at every pixel at once, so the machine needs neither axes nor
// scan-lines; the axes (Yuan et al., Appendix A) only bound the splat for binning, and check the conic.
// Under a parallel camera the splat is a circle about the projected centre.

#include "kernels/shared/screen_regions/screen_projection.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace pp5 {

// A sphere of radius `radius` (world units) about an eye-space centre, as the screen sees it.
struct SplatShape {
    Quadratic inside;             // > 0 inside, as a function of screen position
    glm::dvec2 center;            // of the ellipse (not the projected sphere centre, under perspective)
    glm::dvec2 projected_center;  // the sphere centre's own projection (C' of the paper)
    glm::dvec2 half_extent;       // of the axis-aligned bounding box about `center`
    double peak = 0;              // inside(center): the largest value
    double sin_alpha = 0;         // the cone's half angle (0 under parallel projection)
    double cos2_alpha = 1;
    glm::dvec3 axis{0, 0, 1};  // Q: unit direction from the eye to the centre (parallel: the view)
};

// The splat of the sphere, or nothing when the eye is within reach of it (the cone would not close:
// the kernel reaches the eye's plane) or it lies behind the eye.
std::optional<SplatShape> project_sphere(const ScreenProjection& projection, glm::dvec3 eye_center, double radius);

// Closed forms of the ellipse (checked against the conic in the tests): rho the angle between the view
// axis and Q, alpha the half cone angle, f the focal distance in pixels. Distances are from the
// principal point along the radial direction; a is the radial semi-axis, b the tangential one.
struct EllipseClosedForm {
    double near_edge = 0, far_edge = 0;  // A' and B': f tan(rho - alpha), f tan(rho + alpha)
    double center = 0;                   // f sin(rho) cos(rho) / (cos^2 rho - sin^2 alpha)
    double radial_semi_axis = 0;         // f sin(alpha) cos(alpha) / D
    double tangential_semi_axis = 0;     // f sin(alpha) / sqrt(D)
};
EllipseClosedForm ellipse_closed_form(double rho, double alpha, double focal_pixels);

// The normalized distance d (0 at the kernel's centre line, 1 on its silhouette) of a pixel's ray from
// the sphere's centre, from the affine index i (0 at the ellipse centre, 1 on its edge), as Yuan et al.
// derive it (section 4.2) with their last step corrected: d = sin(atan(i tan a)) / sin(a), that is
// d^2 = i^2 / (cos^2 a + i^2 sin^2 a). (The paper prints tan a in the denominator, which maps the
// silhouette to cos a instead of 1.)
double corrected_index_squared(double i_squared, double sin_alpha);
// The exact d^2 of the ray through screen direction X: (|X|^2 - (X.Q)^2) / (|X|^2 sin^2 a).
double exact_index_squared(const ScreenProjection& projection, const SplatShape& shape, glm::dvec2 screen);

}  // namespace pp5
