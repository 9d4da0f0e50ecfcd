#include "scene/volume/resample.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pp5 {

namespace {

// Where one target index reads on a source axis: two neighbours and the weight of the upper one.
struct Tap {
    int lower = 0;
    int upper = 0;
    float weight = 0.0f;
};

std::vector<Tap> axis_taps(int source_n, int target_n) {
    std::vector<Tap> taps(static_cast<std::size_t>(target_n));
    const double scale = static_cast<double>(source_n) / static_cast<double>(target_n);
    const double last = static_cast<double>(source_n - 1);
    for (int j = 0; j < target_n; ++j) {
        // Double precision so that an identity resample lands exactly on source voxels.
        const double s = std::clamp((static_cast<double>(j) + 0.5) * scale - 0.5, 0.0, last);
        const double base = std::floor(s);
        Tap& t = taps[static_cast<std::size_t>(j)];
        t.lower = static_cast<int>(base);
        t.upper = std::min(t.lower + 1, source_n - 1);
        t.weight = static_cast<float>(s - base);
    }
    return taps;
}

float lerp(float a, float b, float w) { return a + w * (b - a); }

}  // namespace

Volume resample(const Volume& volume, glm::ivec3 target_dims) {
    if (volume.voxel_count() == 0) throw std::invalid_argument("resample: the volume is empty");
    if (target_dims.x < 1 || target_dims.y < 1 || target_dims.z < 1)
        throw std::invalid_argument("resample: every target dimension must be at least 1");
    const glm::ivec3 dims = volume.dims();
    const auto tx = axis_taps(dims.x, target_dims.x);
    const auto ty = axis_taps(dims.y, target_dims.y);
    const auto tz = axis_taps(dims.z, target_dims.z);

    std::vector<float> out;
    out.reserve(static_cast<std::size_t>(target_dims.x) * static_cast<std::size_t>(target_dims.y) *
                static_cast<std::size_t>(target_dims.z));
    for (const Tap& z : tz) {
        for (const Tap& y : ty) {
            for (const Tap& x : tx) {
                const float c00 =
                    lerp(volume.at(x.lower, y.lower, z.lower), volume.at(x.upper, y.lower, z.lower), x.weight);
                const float c10 =
                    lerp(volume.at(x.lower, y.upper, z.lower), volume.at(x.upper, y.upper, z.lower), x.weight);
                const float c01 =
                    lerp(volume.at(x.lower, y.lower, z.upper), volume.at(x.upper, y.lower, z.upper), x.weight);
                const float c11 =
                    lerp(volume.at(x.lower, y.upper, z.upper), volume.at(x.upper, y.upper, z.upper), x.weight);
                out.push_back(lerp(lerp(c00, c10, y.weight), lerp(c01, c11, y.weight), z.weight));
            }
        }
    }
    const glm::vec3 spacing = volume.spacing() * glm::vec3(dims) / glm::vec3(target_dims);
    return Volume(target_dims, spacing, volume.source_type(), std::move(out), volume.name());
}

}  // namespace pp5
