#pragma once
// Small volumes and settings shared by the render tests: built here from closed forms, so the tests
// depend on nothing but the code under test.

#include "scene/render/camera.h"
#include "scene/render/classification.h"
#include "scene/render/image.h"
#include "scene/render/shading.h"
#include "scene/volume/volume.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace pp5::test {

template <class Fn>
Volume make_volume(glm::ivec3 dims, glm::vec3 spacing, Fn&& value_at) {
    std::vector<float> samples;
    samples.reserve(static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) *
                    static_cast<std::size_t>(dims.z));
    for (int z = 0; z < dims.z; ++z) {
        for (int y = 0; y < dims.y; ++y) {
            for (int x = 0; x < dims.x; ++x) samples.push_back(value_at(x, y, z));
        }
    }
    return Volume(dims, spacing, ScalarType::Float32, std::move(samples), "test");
}

inline Volume constant_volume(glm::ivec3 dims, float value, glm::vec3 spacing = glm::vec3(1.0f)) {
    return make_volume(dims, spacing, [&](int, int, int) { return value; });
}

// A ball of value `inside` and radius `radius` voxels about `center`, 0 outside, with a one-voxel
// linear ramp centred on the radius (value inside/2 at exactly `radius`).
inline Volume ball_volume(glm::ivec3 dims, glm::vec3 center, float radius, float inside = 200.0f) {
    return make_volume(dims, glm::vec3(1.0f), [&](int x, int y, int z) {
        const float d = glm::length(glm::vec3(x, y, z) - center);
        return inside * glm::clamp(radius + 0.5f - d, 0.0f, 1.0f);
    });
}

// A deterministic lumpy field: two balls plus a hashed ripple, for invariance tests on odd sizes.
inline Volume lumpy_volume(glm::ivec3 dims) {
    const glm::vec3 c1 = glm::vec3(dims) * glm::vec3(0.35f, 0.4f, 0.5f);
    const glm::vec3 c2 = glm::vec3(dims) * glm::vec3(0.65f, 0.55f, 0.45f);
    const float r = 0.22f * static_cast<float>(std::min({dims.x, dims.y, dims.z}));
    return make_volume(dims, glm::vec3(1.0f), [&](int x, int y, int z) {
        const glm::vec3 p(x, y, z);
        const float a = 150.0f * glm::clamp(r + 0.5f - glm::length(p - c1), 0.0f, 1.0f);
        const float b = 90.0f * glm::clamp(r + 0.5f - glm::length(p - c2), 0.0f, 1.0f);
        const std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u ^
                                static_cast<std::uint32_t>(z) * 83492791u;
        const float ripple = (a + b > 0.0f) ? static_cast<float>(h % 17u) : 0.0f;
        return a + b + ripple;
    });
}

inline Classification piecewise(std::vector<OpacityPoint> points) {
    Classification c;
    c.kind = ClassificationKind::PiecewiseLinear;
    c.points = std::move(points);
    return c;
}

inline Classification constant_opacity(float alpha) { return piecewise({{0.0f, alpha}, {1.0f, alpha}}); }

inline ColorMap constant_color(glm::vec3 c) { return ColorMap{{{0.0f, c}}}; }

// Colour = base colour exactly: ambient 1, no diffuse or specular.
inline PhongLighting flat_lighting() {
    PhongLighting l;
    l.ambient = 1.0f;
    l.diffuse = 0.0f;
    l.specular = 0.0f;
    return l;
}

// A parallel camera on the -z side of a volume looking along +z through (cx, cy).
inline Camera face_on_camera(glm::vec3 center, float view_height) {
    Camera c;
    c.projection = Projection::Parallel;
    c.eye = center - glm::vec3(0.0f, 0.0f, 1000.0f);
    c.target = center;
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    c.view_height = view_height;
    return c;
}

inline bool same_bytes(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec4)) == 0;
}

inline glm::vec3 box_center(const Volume& v) { return 0.5f * glm::vec3(v.dims() - 1) * v.spacing(); }
inline float box_radius(const Volume& v) { return 0.5f * glm::length(glm::vec3(v.dims() - 1) * v.spacing()); }

}  // namespace pp5::test
