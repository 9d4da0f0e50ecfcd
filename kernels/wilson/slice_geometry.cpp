#include "kernels/wilson/slice_geometry.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace pp5 {

SliceStack choose_slices(glm::vec3 view_direction) {
    const glm::vec3 d = glm::abs(view_direction);
    SliceStack stack;
    stack.axis = d.x >= d.y && d.x >= d.z ? 0 : d.y >= d.z ? 1 : 2;
    stack.far_is_high = view_direction[stack.axis] > 0;
    return stack;
}

SlicePlane::SlicePlane(const ScreenProjection& projection, int axis, int index, glm::vec3 spacing, int factor)
    : projection_(&projection),
      axis_(axis),
      b_((axis + 1) % 3),
      c_((axis + 2) % 3),
      plane_(((index + 0.5) * factor - 0.5) * static_cast<double>(spacing[axis])),
      spacing_(spacing),
      factor_(factor),
      perspective_(projection.perspective()) {
    // Each linear function from its values at three screen positions (exact: they are linear).
    const auto numerators = [this](glm::dvec2 s) {
        const glm::dvec3 o = projection_->ray_origin(s), d = projection_->ray_direction(s);
        // W is the ray's rate along the axis, signed so that W > 0 where the plane is ahead of the eye.
        double w = perspective_ ? d[axis_] : 1.0;
        if (perspective_ && (plane_ - o[axis_]) < 0) w = -w;
        const double t_w = perspective_ ? (plane_ - o[axis_]) * (w / d[axis_]) : (plane_ - o[axis_]) / d[axis_];
        // The meeting point times W: o W + t W d.
        const auto texel_w = [&](int k) {
            const double world_w = o[k] * w + t_w * d[k];
            return (world_w / spacing_[k] + 0.5 * w) / factor_ - 0.5 * w + w;  // (texel + 1) W
        };
        return glm::dvec3(texel_w(b_), texel_w(c_), w);
    };
    const glm::dvec3 f0 = numerators({0, 0}), fx = numerators({1, 0}), fy = numerators({0, 1});
    for (int e = 0; e < 3; ++e) linear_[static_cast<std::size_t>(e)] = {fx[e] - f0[e], fy[e] - f0[e], f0[e]};
}

std::optional<glm::dvec2> SlicePlane::texel_at(glm::dvec2 s) const {
    const auto value = [&](int e) {
        const glm::dvec3& l = linear_[static_cast<std::size_t>(e)];
        return l.x * s.x + l.y * s.y + l.z;
    };
    const double w = value(2);
    if (!(w > 0)) return std::nullopt;
    return glm::dvec2(value(0) / w - 1, value(1) / w - 1);
}

glm::dvec3 SlicePlane::world(double u, double v) const {
    glm::dvec3 p(0);
    p[axis_] = plane_;
    p[b_] = ((u + 0.5) * factor_ - 0.5) * spacing_[b_];
    p[c_] = ((v + 0.5) * factor_ - 0.5) * spacing_[c_];
    return p;
}

SliceSetup SlicePlane::setup(int ox, int oy) const {
    SliceSetup s;
    s.perspective = perspective_;
    const auto local = [&](int e) {
        const glm::dvec3& l = linear_[static_cast<std::size_t>(e)];
        return Quadratic{0, 0, 0, l.x, l.y, l.z}.shifted(ox, oy);
    };
    const double scale =
        perspective_ ? static_cast<double>(std::int64_t{1} << SliceFormat::kPerspectiveScaleBits) : 1.0;
    for (int e = 0; e < (perspective_ ? 3 : 2); ++e) {
        const Quadratic q = local(e);
        s.expressions.push_back(to_qee(q.a, q.b, q.c, q.d, q.e, q.f, scale));
    }
    return s;
}

Quadratic cell_quadratic(const SlicePlane& plane, int i, int j, const std::array<std::array<double, 2>, 2>& f,
                         glm::dvec2 center) {
    const double d_u = f[1][0] - f[0][0], d_v = f[0][1] - f[0][0], d_uv = f[0][0] - f[1][0] - f[0][1] + f[1][1];
    const auto bilinear = [&](double u, double v) { return f[0][0] + d_u * u + d_v * v + d_uv * u * v; };
    const auto at = [&](glm::dvec2 s) {
        const std::optional<glm::dvec2> t = plane.texel_at(s);
        return t ? bilinear(t->x - i, t->y - j) : f[0][0];
    };
    if (!plane.perspective()) {
        // u - i and v - j are linear: substitute them.
        const auto linear = [&](int k) {
            const glm::dvec2 t0 = *plane.texel_at({0, 0}), tx = *plane.texel_at({1, 0}), ty = *plane.texel_at({0, 1});
            const double base = k == 0 ? t0.x - i : t0.y - j;
            return glm::dvec3((k == 0 ? tx.x : tx.y) - (k == 0 ? t0.x : t0.y),
                              (k == 0 ? ty.x : ty.y) - (k == 0 ? t0.x : t0.y), base);
        };
        const glm::dvec3 a = linear(0), b = linear(1);  // (d/dx, d/dy, value at the origin)
        Quadratic q;
        q.a = d_uv * a.x * b.x;
        q.b = d_uv * (a.x * b.y + a.y * b.x);
        q.c = d_uv * a.y * b.y;
        q.d = d_u * a.x + d_v * b.x + d_uv * (a.z * b.x + a.x * b.z);
        q.e = d_u * a.y + d_v * b.y + d_uv * (a.z * b.y + a.y * b.z);
        q.f = f[0][0] + d_u * a.z + d_v * b.z + d_uv * a.z * b.z;
        return q;
    }
    // The second-order expansion about the centre's pixel, from central differences one pixel apart.
    const double g = at(center);
    const double gxp = at(center + glm::dvec2(1, 0)), gxm = at(center - glm::dvec2(1, 0));
    const double gyp = at(center + glm::dvec2(0, 1)), gym = at(center - glm::dvec2(0, 1));
    const double gxy = (at(center + glm::dvec2(1, 1)) - at(center + glm::dvec2(1, -1)) -
                        at(center + glm::dvec2(-1, 1)) + at(center + glm::dvec2(-1, -1))) /
                       4;
    const Quadratic about{(gxp - 2 * g + gxm) / 2, gxy, (gyp - 2 * g + gym) / 2, (gxp - gxm) / 2, (gyp - gym) / 2, g};
    return about.substituted(1, -center.x, 1, -center.y);
}

}  // namespace pp5
