#pragma once
// A voxel as the GPs hand it to the renderers: a splat (the quadratic whose value indexes the
// footprint, its colour constants and its footprint row) or a point (a paraboloid of the screen
// position per channel), with the box of pixels it can reach; and the same moved to one region's
// origin and put in the QEE's fixed point (the batch a renderer receives).

#include "kernels/yuan/footprint.h"
#include "kernels/yuan/region_programs.h"
#include "kernels/yuan/splat_geometry.h"

#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>

namespace pp5 {

struct ScreenPrimitive {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;      // screen pixels, inclusive, clipped to the picture
    Quadratic index[2];                        // splat: i^2 in 2^16 units (affine), or N and M (exact)
    Quadratic weight;                          // point: the paraboloid's shape (1 - rho^2 / R^2)
    double channel[4] = {0, 0, 0, 0};          // point: the paraboloid's height per channel, in sheet units
    std::int64_t constants[4] = {0, 0, 0, 0};  // splat: opacity, red, green, blue in accumulator units
    int row = 0;                               // splat: its footprint table
    bool visible() const { return x1 >= x0 && y1 >= y0; }
};

// The splat of a kernel of radius `kernel_world` about an eye-space centre, with the voxel's colour
// and opacity (not premultiplied); nothing when the kernel reaches the eye's plane.
std::optional<ScreenPrimitive> splat_primitive(const ScreenProjection& projection, glm::dvec3 eye, double kernel_world,
                                               glm::vec4 rgba, const FootprintTables& tables, bool exact,
                                               const RegionFormat& format, int width, int height);
// The point of a voxel whose spacing projects to `spacing_pixels`, filtered with radius `radius` pixels:
// it carries the screen area the voxel stands for, so a layer of points covers the screen with its opacity.
ScreenPrimitive point_primitive(const ScreenProjection& projection, glm::dvec3 eye, double spacing_pixels,
                                glm::vec4 rgba, double radius, const RegionFormat& format, int width, int height);

// The primitive as the renderer whose region starts at screen (ox, oy) receives it.
SplatDraw splat_draw(const ScreenPrimitive& splat, int ox, int oy, bool exact);
PointDraw point_draw(const ScreenPrimitive& point, int ox, int oy);

}  // namespace pp5
