#pragma once
// Where the low-resolution volume's axis-aligned slices land on the screen.
//
// A slice is the plane of L's samples at one index along the slicing axis a; the texel coordinates
// (u, v) along the other two axes (b = a + 1, c = a + 2, cyclically) are L's sample indices, so texel
// (i, j) is sample i along b and j along c. A pixel's ray meets the plane at u = U / W and v = V / W,
// with U, V and W linear in the pixel position (W = 1 under a parallel camera). Within texel cell
// (i, j) the colour is bilinear in (u - i, v - j): under a parallel camera that is exactly one
// quadratic of the pixel position; under perspective the quadratic is its second-order expansion about
// the cell centre's pixel (the error is third order in the cell's screen size over its depth).

#include "kernels/shared/screen_regions/screen_projection.h"
#include "kernels/wilson/slice_programs.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <optional>

namespace pp5 {

// How the slices are taken for one view: the axis most parallel to the view, and the order.
struct SliceStack {
    int axis = 2;
    bool far_is_high = true;  // the farthest slice has the highest index
};
// The axis along which the view direction (eye to the volume's centre, or the parallel camera's
// forward) is largest, and which end is far.
SliceStack choose_slices(glm::vec3 view_direction);

// One slice's plane as the screen sees it.
class SlicePlane {
public:
    // `low_spacing`: world size of one low-resolution sample; `factor`: k (samples sit at original
    // coordinate (j + 1/2) k - 1/2, in original voxels of `spacing`).
    SlicePlane(const ScreenProjection& projection, int axis, int index, glm::vec3 spacing, int factor);

    int axis() const { return axis_; }
    // The texel coordinates where the ray through a screen position meets the plane (nothing when the
    // plane is not in front along the ray).
    std::optional<glm::dvec2> texel_at(glm::dvec2 screen) const;
    // The world position of texel coordinates (u, v) on the plane.
    glm::dvec3 world(double u, double v) const;
    // The renderers' setup expressions for the region whose origin is screen (ox, oy).
    SliceSetup setup(int ox, int oy) const;
    bool perspective() const { return perspective_; }

private:
    const ScreenProjection* projection_;
    int axis_, b_, c_;
    double plane_;  // world coordinate along the axis
    glm::dvec3 spacing_;
    int factor_;
    bool perspective_;
    // (u + 1) W, (v + 1) W and W as linear functions {d, e, f} of the screen position, W > 0 in front.
    std::array<glm::dvec3, 3> linear_;
};

// The bilinear colour of a texel cell with corner values `corner[a][b]` (a along u, b along v), as a
// quadratic of the screen position (see above); `center` is the screen position of the cell's centre.
Quadratic cell_quadratic(const SlicePlane& plane, int i, int j, const std::array<std::array<double, 2>, 2>& corner,
                         glm::dvec2 center);

}  // namespace pp5
