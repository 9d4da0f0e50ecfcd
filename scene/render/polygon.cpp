#include "scene/render/polygon.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>

namespace pp5 {

double PreparedPolygon::distance(glm::dvec3 p) const { return glm::dot(normal, p) + plane_offset; }

bool PreparedPolygon::in_sheet(glm::dvec3 p) const {
    if (degenerate || std::abs(distance(p)) > 0.5) return false;
    for (std::size_t i = 0; i < edge_normals.size(); ++i)
        if (glm::dot(edge_normals[i], p) + edge_offsets[i] < 0.0) return false;
    return true;
}

namespace {

// Newell's normal: robust for any planar polygon; its length is twice the area.
glm::dvec3 newell(const std::vector<glm::vec3>& v) {
    glm::dvec3 n(0.0);
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::dvec3 a(v[i]);
        const glm::dvec3 b(v[(i + 1) % v.size()]);
        n += glm::cross(a, b);
    }
    return n;
}

template <class T>
T at_vertex(const std::vector<T>& values, std::size_t i) {
    return values.size() == 1 ? values[0] : values[i];
}

// value(p) = a (p.u) + b (p.w) + h fitted to the vertices by least squares (exact for a triangle).
LinearFunction fit(const std::vector<glm::vec3>& vertices, glm::dvec3 u, glm::dvec3 w,
                   const std::vector<double>& values) {
    double m[3][3] = {};
    double r[3] = {};
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const double row[3] = {glm::dot(u, glm::dvec3(vertices[i])), glm::dot(w, glm::dvec3(vertices[i])), 1.0};
        for (int a = 0; a < 3; ++a) {
            r[a] += row[a] * values[i];
            for (int b = 0; b < 3; ++b) m[a][b] += row[a] * row[b];
        }
    }
    // Cramer's rule on the 3x3 normal equations.
    const auto det3 = [](const double x[3][3]) {
        return x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) - x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
               x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
    };
    const double det = det3(m);
    double mean = 0.0;
    for (double v : values) mean += v;
    mean /= static_cast<double>(values.size());
    if (std::abs(det) < 1e-12) return LinearFunction{glm::vec3(0.0f), static_cast<float>(mean)};
    double solution[3];
    for (int c = 0; c < 3; ++c) {
        double mc[3][3];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) mc[a][b] = b == c ? r[a] : m[a][b];
        solution[c] = det3(mc) / det;
    }
    const glm::dvec3 gradient = solution[0] * u + solution[1] * w;
    return LinearFunction{glm::vec3(gradient), static_cast<float>(solution[2])};
}

}  // namespace

void validate_polygon(const PolygonSpec& polygon, const std::string& file, const std::string& field) {
    const auto& v = polygon.vertices;
    if (v.size() < 3)
        throw InputError(file, field + ".vertices",
                         "a polygon needs at least three vertices, got " + std::to_string(v.size()));
    for (std::size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y) || !std::isfinite(v[i].z))
            throw InputError(file, field + ".vertices", "vertex " + std::to_string(i) + " is not a finite point");
    for (std::size_t i = 0; i < v.size(); ++i)
        for (int k = 0; k < 3; ++k)
            if (std::abs(v[i][k]) > kFarthestPolygonVertex)
                throw InputError(file, field + ".vertices",
                                 fmt::format("vertex {} lies {:g} voxels out along an axis; the renderers' fixed-point "
                                             "plane and edge fields "
                                             "hold coordinates up to {:g}",
                                             i, std::abs(v[i][k]), kFarthestPolygonVertex));
    const auto check_count = [&](std::size_t n, const char* what) {
        if (n != 1 && n != v.size())
            throw InputError(file, field + "." + what,
                             "give one value for the polygon or one per vertex (" + std::to_string(v.size()) +
                                 "), not " + std::to_string(n));
    };
    check_count(polygon.colors.size(), "colors");
    check_count(polygon.opacities.size(), "opacities");
    for (const glm::vec3& c : polygon.colors)
        for (int k = 0; k < 3; ++k)
            if (!(c[k] >= 0.0f && c[k] <= 1.0f))
                throw InputError(file, field + ".colors", "colour components must lie in [0, 1]");
    for (float a : polygon.opacities)
        if (!(a >= 0.0f && a <= 1.0f)) throw InputError(file, field + ".opacities", "opacities must lie in [0, 1]");

    const glm::dvec3 n = newell(v);
    const double twice_area = glm::length(n);
    if (twice_area < 1e-9) return;  // no area: accepted, covers nothing
    const glm::dvec3 unit = n / twice_area;
    const double d0 = glm::dot(unit, glm::dvec3(v[0]));
    for (std::size_t i = 0; i < v.size(); ++i)
        if (std::abs(glm::dot(unit, glm::dvec3(v[i])) - d0) > 0.01)
            throw InputError(file, field + ".vertices",
                             "the vertices are not in one plane (vertex " + std::to_string(i) + " is off it)");
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::dvec3 a(v[i]);
        const glm::dvec3 b(v[(i + 1) % v.size()]);
        const glm::dvec3 c(v[(i + 2) % v.size()]);
        if (glm::dot(glm::cross(b - a, c - b), unit) < -1e-9)
            throw InputError(file, field + ".vertices",
                             "the polygon is not convex at vertex " + std::to_string((i + 1) % v.size()) +
                                 "; split it into convex pieces or triangles");
    }
}

double area_inside_box(const std::vector<glm::vec3>& vertices, glm::dvec3 lower, glm::dvec3 upper) {
    std::vector<glm::dvec3> clipped(vertices.begin(), vertices.end()), next;
    // Sutherland-Hodgman: keep the side of each of the six faces' planes the box is on.
    for (int axis = 0; axis < 3 && !clipped.empty(); ++axis)
        for (const int side : {-1, 1}) {
            const double bound = side < 0 ? lower[axis] : upper[axis];
            const auto inside = [&](const glm::dvec3& p) { return side < 0 ? p[axis] >= bound : p[axis] <= bound; };
            next.clear();
            for (std::size_t i = 0; i < clipped.size(); ++i) {
                const glm::dvec3& a = clipped[i];
                const glm::dvec3& b = clipped[(i + 1) % clipped.size()];
                if (inside(a)) next.push_back(a);
                if (inside(a) != inside(b)) next.push_back(a + (b - a) * ((bound - a[axis]) / (b[axis] - a[axis])));
            }
            clipped.swap(next);
        }
    if (clipped.size() < 3) return 0.0;
    glm::dvec3 n(0.0);
    for (std::size_t i = 0; i < clipped.size(); ++i) n += glm::cross(clipped[i], clipped[(i + 1) % clipped.size()]);
    return 0.5 * glm::length(n);
}

PreparedPolygon prepare_polygon(const PolygonSpec& polygon) {
    PreparedPolygon p;
    const auto& v = polygon.vertices;
    if (v.size() < 3) throw std::invalid_argument("prepare_polygon: fewer than three vertices");
    p.lower = p.upper = v[0];
    for (const glm::vec3& x : v) {
        p.lower = glm::min(p.lower, x);
        p.upper = glm::max(p.upper, x);
    }
    const glm::dvec3 n = newell(v);
    const double twice_area = glm::length(n);
    p.area = 0.5 * twice_area;
    if (twice_area < 1e-9) {
        p.degenerate = true;
        return p;
    }
    p.normal = n / twice_area;
    p.plane_offset = -glm::dot(p.normal, glm::dvec3(v[0]));
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::dvec3 a(v[i]);
        const glm::dvec3 b(v[(i + 1) % v.size()]);
        const glm::dvec3 along = b - a;
        if (glm::length(along) < 1e-12) continue;  // a repeated vertex adds no edge
        const glm::dvec3 inward = glm::normalize(glm::cross(p.normal, along));
        p.edge_normals.push_back(inward);
        p.edge_offsets.push_back(-glm::dot(inward, a));
    }
    // The in-plane axes for the colour fit, from the longest edge (a repeated vertex gives a zero one).
    glm::dvec3 longest(0.0);
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::dvec3 e = glm::dvec3(v[(i + 1) % v.size()]) - glm::dvec3(v[i]);
        if (glm::length(e) > glm::length(longest)) longest = e;
    }
    const glm::dvec3 u = glm::normalize(longest);
    const glm::dvec3 w = glm::cross(p.normal, u);
    std::vector<double> values(v.size());
    LinearFunction* channels[3] = {&p.red, &p.green, &p.blue};
    for (int k = 0; k < 3; ++k) {
        for (std::size_t i = 0; i < v.size(); ++i) values[i] = at_vertex(polygon.colors, i)[k];
        *channels[k] = fit(v, u, w, values);
    }
    for (std::size_t i = 0; i < v.size(); ++i) values[i] = at_vertex(polygon.opacities, i);
    p.opacity = fit(v, u, w, values);
    return p;
}

std::vector<glm::dvec3> subvoxel_offsets(int count) {
    if (count < 1) throw std::invalid_argument("subvoxel_offsets: at least one sample");
    // Roberts' R3 sequence: the generalised golden ratio phi (x^4 = x + 1) gives steps 1/phi^k.
    const double phi = 1.2207440846057596;
    const glm::dvec3 step(1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi));
    std::vector<glm::dvec3> offsets;
    for (int j = 0; j < count; ++j) {
        glm::dvec3 x = 0.5 + static_cast<double>(j) * step;
        x -= glm::floor(x);
        offsets.push_back(x - 0.5);
    }
    return offsets;
}

}  // namespace pp5
