#include "kernels/wilson/hybrid_volume.h"

#include "sim/core/host_memory.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pp5 {

namespace {

// Error samples examined at most (a 2048^3 grid): beyond this the preprocessing would run for hours.
constexpr std::uint64_t kMaxErrorSamples = std::uint64_t{1} << 33;

std::size_t linear(glm::ivec3 dims, int x, int y, int z) {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(dims.x) *
               (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(z));
}

std::uint64_t count(glm::ivec3 d) {
    return static_cast<std::uint64_t>(d.x) * static_cast<std::uint64_t>(d.y) * static_cast<std::uint64_t>(d.z);
}

// Catmull-Rom weights of the four samples around a position t in [0, 1) past the second.
std::array<double, 4> catmull_rom(double t) {
    const double t2 = t * t, t3 = t2 * t;
    return {(-t3 + 2 * t2 - t) / 2, (3 * t3 - 5 * t2 + 2) / 2, (-3 * t3 + 4 * t2 + t) / 2, (t3 - t2) / 2};
}

// Resamples `in` (dims) along one axis to `out_n` samples, sample j at input coordinate position(j),
// with Catmull-Rom weights and the grid's edge values repeated beyond it.
template <class Position>
std::vector<float> resample_axis(const std::vector<float>& in, glm::ivec3 dims, int axis, int out_n,
                                 Position position) {
    glm::ivec3 out_dims = dims;
    out_dims[axis] = out_n;
    std::vector<float> out(count(out_dims));
    const int n = dims[axis];
    struct Tap {
        int index[4];
        std::array<double, 4> weight;
    };
    std::vector<Tap> taps(static_cast<std::size_t>(out_n));
    for (int j = 0; j < out_n; ++j) {
        const double p = position(j);
        const double base = std::floor(p);
        Tap& tap = taps[static_cast<std::size_t>(j)];
        tap.weight = catmull_rom(p - base);
        for (int m = 0; m < 4; ++m) tap.index[m] = std::clamp(static_cast<int>(base) - 1 + m, 0, n - 1);
    }
    pp5::parallel_for(0, out_dims.z, [&](int z) {
        glm::ivec3 at;
        for (int y = 0; y < out_dims.y; ++y)
            for (int x = 0; x < out_dims.x; ++x) {
                at = {x, y, z};
                const Tap& tap = taps[static_cast<std::size_t>(at[axis])];
                double sum = 0;
                for (int m = 0; m < 4; ++m) {
                    glm::ivec3 src = at;
                    src[axis] = tap.index[m];
                    sum += tap.weight[static_cast<std::size_t>(m)] * in[linear(dims, src.x, src.y, src.z)];
                }
                out[linear(out_dims, x, y, z)] = static_cast<float>(sum);
            }
    });
    return out;
}

// The original tricubically resampled onto a grid of `out` samples whose sample j sits at input
// coordinate position(j) on every axis.
template <class Position>
std::vector<float> resample_cubic(const Volume& v, glm::ivec3 out, Position position) {
    std::vector<float> data(v.samples().begin(), v.samples().end());
    glm::ivec3 dims = v.dims();
    for (int axis = 0; axis < 3; ++axis) {
        data = resample_axis(data, dims, axis, out[axis], position);
        dims[axis] = out[axis];
    }
    for (float& x : data) x = std::clamp(x, v.min_value(), v.max_value());
    return data;
}

float trilinear(std::span<const float> data, glm::ivec3 dims, glm::vec3 p) {
    const glm::vec3 c = glm::clamp(p, glm::vec3(0.0f), glm::vec3(dims - 1));
    const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(c)), dims - 1);
    const glm::ivec3 i1 = glm::min(i0 + 1, dims - 1);
    const glm::vec3 t = c - glm::vec3(i0);
    const auto at = [&](int x, int y, int z) { return data[linear(dims, x, y, z)]; };
    const float c00 = at(i0.x, i0.y, i0.z) * (1 - t.x) + at(i1.x, i0.y, i0.z) * t.x;
    const float c10 = at(i0.x, i1.y, i0.z) * (1 - t.x) + at(i1.x, i1.y, i0.z) * t.x;
    const float c01 = at(i0.x, i0.y, i1.z) * (1 - t.x) + at(i1.x, i0.y, i1.z) * t.x;
    const float c11 = at(i0.x, i1.y, i1.z) * (1 - t.x) + at(i1.x, i1.y, i1.z) * t.x;
    return (c00 * (1 - t.y) + c10 * t.y) * (1 - t.z) + (c01 * (1 - t.y) + c11 * t.y) * t.z;
}

// The low-resolution samples from the original by the chosen filter.
std::vector<float> downsample(const Volume& v, int k, glm::ivec3 low, const WilsonSettings& s) {
    const glm::ivec3 dims = v.dims();
    const auto centre = [k](int j) { return (j + 0.5) * k - 0.5; };
    std::vector<float> out;
    if (s.downsample == Downsample::Cubic) out = resample_cubic(v, low, centre);
    if (s.downsample == Downsample::Box) {
        out.assign(count(low), 0.0f);
        pp5::parallel_for(0, low.z, [&](int z) {
            for (int y = 0; y < low.y; ++y)
                for (int x = 0; x < low.x; ++x) {
                    double sum = 0;
                    int n = 0;
                    for (int c = z * k; c < std::min((z + 1) * k, dims.z); ++c)
                        for (int b = y * k; b < std::min((y + 1) * k, dims.y); ++b)
                            for (int a = x * k; a < std::min((x + 1) * k, dims.x); ++a, ++n) sum += v.at(a, b, c);
                    out[linear(low, x, y, z)] = static_cast<float>(sum / n);
                }
        });
    }
    if (s.downsample != Downsample::Minimum && !std::isfinite(s.overestimate_limit)) return out;
    // The least voxel under each sample's trilinear hat: the voxels strictly within one sample
    // spacing of its centre (those its hat weighs). Any trilinear mix of such minima is at most the
    // voxel it is evaluated at.
    std::vector<float> least(count(low));
    const auto range = [&](int j, int n) {
        const double c = centre(j);
        return std::pair<int, int>{std::max(0, static_cast<int>(std::floor(c - k)) + 1),
                                   std::min(n - 1, static_cast<int>(std::ceil(c + k)) - 1)};
    };
    pp5::parallel_for(0, low.z, [&](int z) {
        const auto [z0, z1] = range(z, dims.z);
        for (int y = 0; y < low.y; ++y) {
            const auto [y0, y1] = range(y, dims.y);
            for (int x = 0; x < low.x; ++x) {
                const auto [x0, x1] = range(x, dims.x);
                float m = v.max_value();
                for (int c = z0; c <= z1; ++c)
                    for (int b = y0; b <= y1; ++b)
                        for (int a = x0; a <= x1; ++a) m = std::min(m, v.at(a, b, c));
                least[linear(low, x, y, z)] = m;
            }
        }
    });
    if (s.downsample == Downsample::Minimum) return least;
    const float limit = static_cast<float>(s.overestimate_limit);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::min(out[i], least[i] + limit);
    return out;
}

struct Candidate {
    std::uint64_t index = 0;  // linear on the error grid
    float error = 0;          // share of the value range
};

// The error-grid samples where the low-resolution volume errs past the threshold (with the sign rule),
// the largest s.max_points of them when there are more, in grid order; and the errors' account.
std::vector<Candidate> choose_points(std::span<const float> original, const Volume& low, glm::ivec3 grid, int k, int g,
                                     float range, const WilsonSettings& s, PointSelection& sel) {
    // Errors, plane by plane in parallel; candidates kept in grid order.
    std::vector<std::vector<Candidate>> per_plane(static_cast<std::size_t>(grid.z));
    std::vector<double> abs_sums(static_cast<std::size_t>(grid.z), 0.0);
    std::vector<float> largest(static_cast<std::size_t>(grid.z), 0.0f);
    std::vector<std::array<std::uint64_t, 5>> paper_counts(static_cast<std::size_t>(grid.z),
                                                           std::array<std::uint64_t, 5>{});
    if (range > 0) {
        pp5::parallel_for(0, grid.z, [&](int z) {
            auto& out = per_plane[static_cast<std::size_t>(z)];
            double sum = 0;
            float most = 0;
            for (int y = 0; y < grid.y; ++y)
                for (int x = 0; x < grid.x; ++x) {
                    const std::size_t i = linear(grid, x, y, z);
                    const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f) / static_cast<float>(g) - 0.5f;
                    const float e = (original[i] - reconstruct_low_resolution(low, k, p)) / range;
                    sum += std::abs(e);
                    most = std::max(most, std::abs(e));
                    const float signed_error = s.error_sign == ErrorSign::Positive ? e : std::abs(e);
                    if (signed_error > s.error_threshold) out.push_back(Candidate{i, e});
                    for (std::size_t t = 0; t < kPaperThresholds.size(); ++t)
                        paper_counts[static_cast<std::size_t>(z)][t] += signed_error > kPaperThresholds[t] ? 1 : 0;
                }
            abs_sums[static_cast<std::size_t>(z)] = sum;
            largest[static_cast<std::size_t>(z)] = most;
        });
    }
    std::vector<Candidate> chosen;
    for (auto& plane : per_plane) chosen.insert(chosen.end(), plane.begin(), plane.end());
    sel.error_samples = count(grid);
    sel.above_threshold = chosen.size();
    for (const Candidate& c : chosen) sel.underestimates += c.error > 0 ? 1 : 0;
    for (std::size_t z = 0; z < abs_sums.size(); ++z) {
        for (std::size_t t = 0; t < kPaperThresholds.size(); ++t) sel.at_paper_thresholds[t] += paper_counts[z][t];
        sel.mean_abs_error += abs_sums[z];
        sel.largest_error = std::max(sel.largest_error, static_cast<double>(largest[z]));
    }
    sel.mean_abs_error /= static_cast<double>(sel.error_samples);
    if (s.max_points > 0 && chosen.size() > s.max_points) {
        // The largest errors, ties to the earlier sample; then back into grid (storage) order.
        std::nth_element(chosen.begin(), chosen.begin() + static_cast<std::ptrdiff_t>(s.max_points), chosen.end(),
                         [](const Candidate& a, const Candidate& b) {
                             const float ea = std::abs(a.error), eb = std::abs(b.error);
                             return ea != eb ? ea > eb : a.index < b.index;
                         });
        chosen.resize(s.max_points);
        std::sort(chosen.begin(), chosen.end(),
                  [](const Candidate& a, const Candidate& b) { return a.index < b.index; });
    }
    return chosen;
}

}  // namespace

NormalTable::NormalTable() {
    // Spherical Fibonacci: z evenly spaced, longitude advancing by the golden angle.
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < kDirections; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / kDirections;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = golden * i;
        directions_[static_cast<std::size_t>(i)] = glm::vec3(
            static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)), static_cast<float>(z));
    }
}

const NormalTable& NormalTable::get() {
    static const NormalTable table;
    return table;
}

std::uint8_t NormalTable::nearest(glm::vec3 n) const {
    if (n == glm::vec3(0.0f)) return kNone;
    int best = 0;
    float best_dot = -2.0f;
    for (int i = 0; i < kDirections; ++i) {
        const float d = glm::dot(n, directions_[static_cast<std::size_t>(i)]);
        if (d > best_dot) {
            best_dot = d;
            best = i;
        }
    }
    return static_cast<std::uint8_t>(best);
}

PointFormat PointFormat::for_grid(glm::ivec3 grid, int value_bytes, bool gradient_byte) {
    const bool small = grid.x <= 256 && grid.y <= 256 && grid.z <= 256;
    return PointFormat{small ? 1 : 2, value_bytes, gradient_byte};
}

std::uint64_t HybridStorage::volume_bytes() const { return count(low_resolution) * voxel_bytes(); }

float reconstruct_low_resolution(const Volume& low, int factor, glm::vec3 p) {
    const glm::vec3 c = (p + 0.5f) / static_cast<float>(factor) - 0.5f;
    return trilinear(low.samples(), low.dims(), c);
}

HybridVolume HybridVolume::build(const Volume& v, const WilsonSettings& s, bool gradient_byte) {
    HybridVolume h;
    const int k = s.downsample_factor;
    const int g = s.error_grid_factor;
    const glm::ivec3 dims = v.dims();
    const glm::ivec3 low = (dims + k - 1) / k;
    h.factor_ = k;
    h.grid_ = dims * g;
    // The renderers' cell keys hold 12-bit indices (slice_programs.h).
    if (glm::any(glm::greaterThan(low, glm::ivec3(4093))))
        reject_field(
            "wilson.downsample_factor",
            fmt::format("a {}x{}x{} low-resolution volume has more than the renderers' 4093 cells along an axis; "
                        "raise the factor",
                        low.x, low.y, low.z));
    h.grid_factor_ = g;
    if (count(h.grid_) > kMaxErrorSamples)
        reject_field(
            "wilson.error_grid_factor",
            fmt::format("an error grid of {}x{}x{} samples is more than the {} this preprocessing examines; lower "
                        "the factor",
                        h.grid_.x, h.grid_.y, h.grid_.z, kMaxErrorSamples));
    if (g > 1)
        check_fits_host_memory("", "wilson.error_grid_factor", static_cast<double>(count(h.grid_)) * sizeof(float),
                               fmt::format("interpolating the volume onto a {}x{}x{} error grid (lower the factor)",
                                           h.grid_.x, h.grid_.y, h.grid_.z));
    h.low_ = Volume(low, v.spacing() * static_cast<float>(k), v.source_type(), downsample(v, k, low, s),
                    v.name() + " (low resolution)");

    // The original on the error grid: itself, or tricubically interpolated.
    std::vector<float> fine;
    if (g > 1) fine = resample_cubic(v, h.grid_, [g](int i) { return (i + 0.5) / g - 0.5; });
    const std::span<const float> original = g > 1 ? std::span<const float>(fine) : v.samples();
    h.value_min_ = v.min_value();
    h.value_range_ = v.max_value() - v.min_value();
    const float range = h.value_range_;

    const std::vector<Candidate> chosen = choose_points(original, h.low_, h.grid_, k, g, range, s, h.selection_);

    // The records: gradients by central differences of the (interpolated) original at the point.
    const int value_bytes = scalar_size_bytes(v.source_type()) == 1 ? 1 : 2;
    h.format_ = PointFormat::for_grid(h.grid_, value_bytes, gradient_byte);
    const double value_steps = value_bytes == 1 ? 255.0 : 65535.0;
    std::vector<glm::vec3> gradients(chosen.size());
    h.points_.resize(chosen.size());
    const glm::ivec3 grid = h.grid_;
    pp5::parallel_for(std::size_t{0}, chosen.size(), [&](std::size_t n) {
        const std::uint64_t i = chosen[n].index;
        const int x = static_cast<int>(i % static_cast<std::uint64_t>(grid.x));
        const int y = static_cast<int>((i / static_cast<std::uint64_t>(grid.x)) % static_cast<std::uint64_t>(grid.y));
        const int z = static_cast<int>(i / (static_cast<std::uint64_t>(grid.x) * static_cast<std::uint64_t>(grid.y)));
        HybridPoint& p = h.points_[n];
        p.x = static_cast<std::uint16_t>(x);
        p.y = static_cast<std::uint16_t>(y);
        p.z = static_cast<std::uint16_t>(z);
        const float value = original[i];
        p.value = static_cast<std::uint16_t>(
            std::lround(std::clamp((value - h.value_min_) / range, 0.0f, 1.0f) * value_steps));
        p.error = static_cast<std::int8_t>(std::clamp(std::lround(chosen[n].error * 127.0f), -127L, 127L));
        // Central differences over one original voxel either side, halved (value units per voxel).
        const auto at = [&](glm::vec3 q) {
            return trilinear(original, grid, (q + 0.5f) * static_cast<float>(g) - 0.5f);
        };
        const glm::vec3 pos = (glm::vec3(x, y, z) + 0.5f) / static_cast<float>(g) - 0.5f;
        const glm::vec3 grad(at(pos + glm::vec3(1, 0, 0)) - at(pos - glm::vec3(1, 0, 0)),
                             at(pos + glm::vec3(0, 1, 0)) - at(pos - glm::vec3(0, 1, 0)),
                             at(pos + glm::vec3(0, 0, 1)) - at(pos - glm::vec3(0, 0, 1)));
        gradients[n] = grad * 0.5f;
        const float length = glm::length(gradients[n]);
        p.normal = length > 0 ? NormalTable::get().nearest(-gradients[n] / length) : NormalTable::kNone;
    });
    for (const glm::vec3& grad : gradients) h.gradient_max_ = std::max(h.gradient_max_, glm::length(grad));
    for (std::size_t n = 0; n < h.points_.size(); ++n)
        h.points_[n].gradient =
            h.gradient_max_ > 0
                ? static_cast<std::uint8_t>(std::lround(glm::length(gradients[n]) / h.gradient_max_ * 255.0f))
                : 0;
    return h;
}

HybridStorage HybridVolume::storage() const {
    return HybridStorage{low_.dims(), format_.value_bytes, format_.gradient_byte, points_.size(), format_};
}

glm::vec3 HybridVolume::position(const HybridPoint& p) const {
    return (glm::vec3(p.x, p.y, p.z) + 0.5f) / static_cast<float>(grid_factor_) - 0.5f;
}

float HybridVolume::value(const HybridPoint& p) const {
    const float steps = format_.value_bytes == 1 ? 255.0f : 65535.0f;
    return value_min_ + static_cast<float>(p.value) / steps * value_range_;
}

float HybridVolume::error(const HybridPoint& p) const { return static_cast<float>(p.error) / 127.0f * value_range_; }

float HybridVolume::gradient_magnitude(const HybridPoint& p) const {
    return static_cast<float>(p.gradient) / 255.0f * gradient_max_;
}

}  // namespace pp5
