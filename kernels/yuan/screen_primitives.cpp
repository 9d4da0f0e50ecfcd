#include "kernels/yuan/screen_primitives.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pp5 {

namespace {

std::int64_t to_units(float v, std::int64_t one) {
    return std::clamp<std::int64_t>(
        static_cast<std::int64_t>(std::lround(static_cast<double>(v) * static_cast<double>(one))), 0, one);
}

// One pixel of margin: the fixed-point quadratic may reach a pixel the float box just misses.
void set_box(ScreenPrimitive& p, double x0, double y0, double x1, double y1, int width, int height) {
    p.x0 = std::max(0, static_cast<int>(std::floor(x0)) - 1);
    p.y0 = std::max(0, static_cast<int>(std::floor(y0)) - 1);
    p.x1 = std::min(width - 1, static_cast<int>(std::ceil(x1)) + 1);
    p.y1 = std::min(height - 1, static_cast<int>(std::ceil(y1)) + 1);
}

}  // namespace

std::optional<ScreenPrimitive> splat_primitive(const ScreenProjection& projection, glm::dvec3 eye, double kernel_world,
                                               glm::vec4 rgba, const FootprintTables& tables, bool exact,
                                               const RegionFormat& format, int width, int height) {
    const std::optional<SplatShape> shape = project_sphere(projection, eye, kernel_world);
    if (!shape) return std::nullopt;
    ScreenPrimitive p;
    const double scale = static_cast<double>(std::int64_t{1} << RegionFormat::kIndexBits);
    if (exact && projection.perspective()) {
        // d^2 = N / M with N = (|X|^2 - (X.Q)^2) / (f^2 sin^2 a) and M = |X|^2 / f^2, both in 2^16 units.
        const glm::dvec2 pp = projection.principal_point();
        const double f = projection.focal_pixels();
        const glm::dvec3 q = shape->axis;
        const Quadratic length2 = Quadratic{1, 0, 1, 0, 0, f * f}.substituted(1, -pp.x, -1, pp.y);
        const Quadratic along2 =
            Quadratic{q.x * q.x, 2 * q.x * q.y, q.y * q.y, 2 * f * q.x * q.z, 2 * f * q.y * q.z, f * f * q.z * q.z}
                .substituted(1, -pp.x, -1, pp.y);
        const Quadratic off_axis{length2.a - along2.a, length2.b - along2.b, length2.c - along2.c,
                                 length2.d - along2.d, length2.e - along2.e, length2.f - along2.f};
        p.index[0] = off_axis.scaled(scale / (f * f * shape->sin_alpha * shape->sin_alpha));
        p.index[1] = length2.scaled(scale / (f * f));
    } else {
        // i^2 = 1 - E / E(centre): 0 at the ellipse's centre, 1 on its edge.
        p.index[0] = shape->inside.scaled(-scale / shape->peak);
        p.index[0].f += scale;
    }
    p.row = tables.row_of(std::asin(std::min(shape->sin_alpha, 1.0)));
    const std::int64_t one = format.one();
    p.constants[0] = to_units(rgba.a, one);
    for (int c = 0; c < 3; ++c) p.constants[c + 1] = std::min(to_units(rgba[c], one), one - 1);
    set_box(p, shape->center.x - shape->half_extent.x, shape->center.y - shape->half_extent.y,
            shape->center.x + shape->half_extent.x, shape->center.y + shape->half_extent.y, width, height);
    return p;
}

ScreenPrimitive point_primitive(const ScreenProjection& projection, glm::dvec3 eye, double spacing_pixels,
                                glm::vec4 rgba, double radius, const RegionFormat& format, int width, int height) {
    ScreenPrimitive p;
    const glm::dvec2 at = projection.to_screen(eye);
    const double r2 = radius * radius;
    p.weight = Quadratic{-1 / r2, 0, -1 / r2, 2 * at.x / r2, 2 * at.y / r2, 1 - (at.x * at.x + at.y * at.y) / r2};
    // The paraboloid (2 / pi R^2)(1 - rho^2 / R^2) has unit area; times the voxel's screen area.
    const double energy = spacing_pixels * spacing_pixels * 2.0 / (std::numbers::pi * r2) * rgba.a *
                          static_cast<double>(format.sheet_one());
    for (int c = 0; c < 3; ++c) p.channel[c] = energy * rgba[c];
    p.channel[3] = energy;
    set_box(p, at.x - radius, at.y - radius, at.x + radius, at.y + radius, width, height);
    return p;
}

SplatDraw splat_draw(const ScreenPrimitive& splat, int ox, int oy, bool exact) {
    SplatDraw draw;
    for (int q = 0; q < (exact ? 2 : 1); ++q) {
        const Quadratic local = splat.index[q].shifted(ox, oy);
        // N and M are never negative: one unit of bias keeps their rounding from going below zero.
        draw.expressions.push_back(
            to_qee(local.a, local.b, local.c, local.d, local.e, local.f, 1.0, exact ? 1.0 : 0.0));
    }
    for (const std::int64_t c : splat.constants) draw.expressions.push_back(qee_constant(c));
    draw.table = splat.row;
    draw.x0 = splat.x0 - ox, draw.y0 = splat.y0 - oy, draw.x1 = splat.x1 - ox, draw.y1 = splat.y1 - oy;
    return draw;
}

PointDraw point_draw(const ScreenPrimitive& point, int ox, int oy) {
    PointDraw draw;
    const Quadratic local = point.weight.shifted(ox, oy);
    for (int c = 0; c < 4; ++c)
        // Half a unit of bias rounds each weight instead of flooring it: a pixel under a hundred minified
        // points would otherwise lose a unit to each.
        draw.expressions[static_cast<std::size_t>(c)] =
            to_qee(local.a, local.b, local.c, local.d, local.e, local.f, point.channel[c], 0.5);
    draw.x0 = point.x0 - ox, draw.y0 = point.y0 - oy, draw.x1 = point.x1 - ox, draw.y1 = point.y1 - oy;
    return draw;
}

}  // namespace pp5
