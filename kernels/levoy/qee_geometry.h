#pragma once
// What the polygon and region programs share (geometry_programs.cpp, region_programs.cpp): linear
// functions of a voxel's position as QEE coefficients, and the box the volume's voxels fill.

#include "kernels/shared/pp_volume/shading_programs.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace pp5::qee_geometry {

inline constexpr double kScale = static_cast<double>(std::int64_t{1} << kQeeShift);

// f(p) = dot(g, p) + h at p = origin + (column, row, 0) + offset, times `scale`, as QEE coefficients.
inline QeeCoefficients linear(glm::dvec3 g, double h, glm::dvec3 origin, double scale) {
    QeeCoefficients q;
    q.d = std::llround(g.x * scale);
    q.e = std::llround(g.y * scale);
    q.f = std::llround((glm::dot(g, origin) + h) * scale);
    return q;
}

// Corner c (0 to 7) of the box [lo, hi].
inline glm::dvec3 box_corner(int c, glm::dvec3 lo, glm::dvec3 hi) {
    return {(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
}

// The volume's voxels with a voxel of margin on every side.
inline glm::dvec3 volume_lower() { return glm::dvec3(-1.0); }
inline glm::dvec3 volume_upper(glm::ivec3 dims) { return glm::dvec3(dims); }

}  // namespace pp5::qee_geometry
