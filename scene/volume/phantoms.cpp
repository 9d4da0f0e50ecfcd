#include "scene/volume/phantoms.h"

#include "sim/core/input_error.h"
#include "sim/core/spelling.h"

#include <fmt/core.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace pp5 {

namespace {

template <class Fn>
std::vector<float> fill(glm::ivec3 dims, Fn&& value_at) {
    std::vector<float> samples;
    samples.reserve(static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) *
                    static_cast<std::size_t>(dims.z));
    for (int z = 0; z < dims.z; ++z) {
        for (int y = 0; y < dims.y; ++y) {
            for (int x = 0; x < dims.x; ++x) samples.push_back(value_at(glm::vec3(x, y, z)));
        }
    }
    return samples;
}

// Share of a voxel inside a surface, given its signed distance from it (negative inside): a ramp one
// voxel wide, which a gradient estimator sees as a smooth edge rather than a staircase.
float coverage(float signed_distance) { return std::clamp(0.5f - signed_distance, 0.0f, 1.0f); }

struct Ellipsoid {
    glm::vec3 center;
    glm::vec3 semi_axes;  // voxels

    // First-order signed distance g / |grad g| with g = |q| - 1, q = (p - c) / axes: exact on the
    // surface and close within a voxel of it, which is all the edge ramp needs.
    float signed_distance(glm::vec3 p) const {
        const glm::vec3 q = (p - center) / semi_axes;
        const float k = glm::length(q);
        if (k == 0.0f) return -std::min({semi_axes.x, semi_axes.y, semi_axes.z});
        const float gradient = glm::length(q / semi_axes) / k;
        return (k - 1.0f) / gradient;
    }
};

void require(bool ok, const char* message) {
    if (!ok) throw std::invalid_argument(message);
}

constexpr std::array<std::string_view, 3> kPhantomNames{"sphere", "checker-box", "head"};
constexpr int kMaxPhantomSize = 1024;

}  // namespace

Volume make_sphere_phantom(int n, float radius_fraction) {
    require(n >= 1, "make_sphere_phantom: n must be at least 1");
    require(radius_fraction > 0.0f, "make_sphere_phantom: radius_fraction must be positive");
    const glm::ivec3 dims(n);
    const glm::vec3 center(0.5f * static_cast<float>(n - 1));
    const float radius = radius_fraction * static_cast<float>(n);
    auto samples = fill(dims, [&](glm::vec3 p) { return 200.0f * coverage(glm::length(p - center) - radius); });
    return Volume(dims, glm::vec3(1.0f), ScalarType::UInt8, std::move(samples), "sphere");
}

Volume make_checker_box_phantom(int n, int cell) {
    require(n >= 1, "make_checker_box_phantom: n must be at least 1");
    require(cell >= 1, "make_checker_box_phantom: cell must be at least 1");
    const glm::ivec3 dims(n);
    auto samples = fill(dims, [&](glm::vec3 p) {
        const int parity =
            (static_cast<int>(p.x) / cell + static_cast<int>(p.y) / cell + static_cast<int>(p.z) / cell) % 2;
        return parity == 0 ? 200.0f : 100.0f;
    });
    return Volume(dims, glm::vec3(1.0f), ScalarType::UInt8, std::move(samples), "checker-box");
}

Volume make_head_phantom(int n) {
    require(n >= 1, "make_head_phantom: n must be at least 1");
    const glm::ivec3 dims(n);
    const glm::vec3 center(0.5f * static_cast<float>(n - 1));
    const float unit = 0.5f * static_cast<float>(n);
    const Ellipsoid skin{center, unit * glm::vec3(0.70f, 0.88f, 0.80f)};
    const Ellipsoid skull{center, unit * glm::vec3(0.64f, 0.82f, 0.74f)};
    const Ellipsoid brain{center, unit * glm::vec3(0.56f, 0.74f, 0.66f)};
    const glm::vec3 ventricle_axes = unit * glm::vec3(0.07f, 0.24f, 0.12f);
    const Ellipsoid left{center + unit * glm::vec3(-0.11f, 0.02f, 0.08f), ventricle_axes};
    const Ellipsoid right{center + unit * glm::vec3(0.11f, 0.02f, 0.08f), ventricle_axes};

    auto samples = fill(dims, [&](glm::vec3 p) {
        // Painted from the outside in, each layer blended over the last by its coverage, so each
        // boundary ramps between the two layers that meet there. An inner layer is looked at only
        // where the one around it is present: most of the box is air, and skipping it keeps a 256^3
        // head near 0.3 s.
        const float skin_cover = coverage(skin.signed_distance(p));
        if (skin_cover == 0.0f) return 0.0f;
        float v = 60.0f * skin_cover;
        v += (220.0f - v) * coverage(skull.signed_distance(p));
        const float brain_cover = coverage(brain.signed_distance(p));
        if (brain_cover == 0.0f) return v;
        v += (110.0f - v) * brain_cover;
        const float ventricles = std::max(coverage(left.signed_distance(p)), coverage(right.signed_distance(p)));
        v += (30.0f - v) * ventricles;
        return v;
    });
    return Volume(dims, glm::vec3(1.0f), ScalarType::UInt8, std::move(samples), "head");
}

Volume make_constant_volume(glm::ivec3 dims, float value) {
    require(dims.x >= 1 && dims.y >= 1 && dims.z >= 1, "make_constant_volume: every dimension must be at least 1");
    std::vector<float> samples(
        static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z), value);
    return Volume(dims, glm::vec3(1.0f), ScalarType::Float32, std::move(samples), "constant");
}

std::span<const std::string_view> phantom_names() { return kPhantomNames; }

Volume make_phantom(std::string_view name, int n) {
    const auto known = std::find(kPhantomNames.begin(), kPhantomNames.end(), name);
    if (known == kPhantomNames.end()) {
        throw InputError("", "phantom",
                         fmt::format("unknown phantom \"{}\"{} (known: {})", name,
                                     did_you_mean(name, std::vector<std::string>(std::begin(kPhantomNames),
                                                                                 std::end(kPhantomNames))),
                                     fmt::join(kPhantomNames, ", ")));
    }
    if (n < 1 || n > kMaxPhantomSize) {
        throw InputError("", "size", fmt::format("{} is outside 1..{} for phantom \"{}\"", n, kMaxPhantomSize, name));
    }
    if (name == "sphere") return make_sphere_phantom(n);
    if (name == "checker-box") return make_checker_box_phantom(n);
    return make_head_phantom(n);
}

}  // namespace pp5
