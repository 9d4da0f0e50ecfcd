#pragma once
// Where world points land on the screen, for the kernels whose renderers draw screen-region
// primitives: eye-space coordinates, pixel positions and the local magnification, and the quadratics
// of the screen position that the renderers' QEE evaluates.
//
// Screen coordinates are pixel indices: pixel (i, j)'s centre is (i, j), j down from the top row (the
// same pixel centres as PixelRays).

#include "scene/render/camera.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pp5 {

// A quadratic of two variables: a x^2 + b x y + c y^2 + d x + e y + f.
struct Quadratic {
    double a = 0, b = 0, c = 0, d = 0, e = 0, f = 0;
    double operator()(double x, double y) const { return a * x * x + b * x * y + c * y * y + d * x + e * y + f; }
    // The same function of (s, t) where x = sx s + x0 and y = sy t + y0.
    Quadratic substituted(double sx, double x0, double sy, double y0) const;
    Quadratic scaled(double k) const { return {a * k, b * k, c * k, d * k, e * k, f * k}; }
    // In coordinates whose origin is (x0, y0): q'(x, y) = q(x + x0, y + y0).
    Quadratic shifted(double x0, double y0) const { return substituted(1, x0, 1, y0); }
};

// The camera as the splatter needs it: eye-space coordinates of world points and their pixels.
class ScreenProjection {
public:
    ScreenProjection(const Camera& camera, int width, int height);
    bool perspective() const { return perspective_; }
    // Eye space: x right, y up, z along the view (world units).
    glm::dvec3 to_eye(glm::vec3 world) const;
    // The screen position of an eye-space point (z > 0 under perspective).
    glm::dvec2 to_screen(glm::dvec3 eye) const;
    // Pixels per world unit at eye depth z: the local magnification.
    double pixels_per_unit(double z) const { return perspective_ ? focal_ / z : pixels_per_unit_; }
    double focal_pixels() const { return focal_; }  // perspective: the image plane's distance in pixels
    glm::dvec2 principal_point() const { return principal_; }
    // The ray through a screen position, in world space: where it starts (the eye under perspective)
    // and its direction, not normalised; both are linear in the screen position.
    glm::dvec3 ray_origin(glm::dvec2 screen) const;
    glm::dvec3 ray_direction(glm::dvec2 screen) const;

private:
    bool perspective_;
    glm::dvec3 eye_;
    glm::dvec3 right_, up_, forward_;
    double focal_ = 0;            // perspective
    double pixels_per_unit_ = 0;  // parallel
    glm::dvec2 principal_;        // the screen position of the view axis
};

}  // namespace pp5
