#include "kernels/perm/perm_structure.h"

#include "kernels/reference/gradient_field.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace pp5 {

namespace {

std::uint64_t cube(int n) { return static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n); }

// Trilinear interpolation inside one cell from its eight corners (index by x + 2y + 4z).
template <class T>
T in_cell(const T (&c)[8], glm::vec3 w) {
    const auto lerp = [](const T& a, const T& b, float t) { return a + (b - a) * t; };
    const T x00 = lerp(c[0], c[1], w.x), x10 = lerp(c[2], c[3], w.x), x01 = lerp(c[4], c[5], w.x), x11 = lerp(c[6], c[7], w.x);
    return lerp(lerp(x00, x10, w.y), lerp(x01, x11, w.y), w.z);
}

}  // namespace

std::uint64_t PermMemory::index_volume_bytes() const {
    return static_cast<std::uint64_t>(dims.x) * static_cast<std::uint64_t>(dims.y) * static_cast<std::uint64_t>(dims.z) *
           static_cast<std::uint64_t>(index_bytes);
}

std::uint64_t PermMemory::summed_table_bytes() const { return index_bytes == 2 ? 4 * static_cast<std::uint64_t>(dims.z) : 0; }

std::uint64_t PermMemory::record_bytes() const {
    return cube(density_positions) * static_cast<std::uint64_t>(density_bytes) +
           cube(gradient_positions) * static_cast<std::uint64_t>(3 * kGradientBytes + kSignBytes);
}

std::uint64_t PermMemory::total_bytes() const { return index_volume_bytes() + summed_table_bytes() + candidates * record_bytes(); }

PositionTable::PositionTable(int positions, int qbm, QuantizedPositions rule)
    : positions_(positions), qbm_(qbm), rule_(rule), table_(static_cast<std::size_t>(qbm)) {
    const double t = static_cast<double>(qbm) / positions;  // eq. (4)'s t = QBM / N_qc
    for (int qi = 0; qi < qbm; ++qi) {
        int k;
        if (rule == QuantizedPositions::Centers) {
            k = static_cast<int>(static_cast<std::int64_t>(qi) * positions / qbm);
        } else {
            k = static_cast<int>(std::floor(qi / t)) + (std::fmod(static_cast<double>(qi), t) < t / 2 ? 0 : 1);
            if (rule == QuantizedPositions::Rounded) k = std::min(k, positions - 1);
        }
        table_[static_cast<std::size_t>(qi)] = k;
    }
}

int PositionTable::index(float fraction) const {
    const int qi = std::clamp(static_cast<int>(std::floor(static_cast<double>(qbm_) * fraction)), 0, qbm_ - 1);
    return table_[static_cast<std::size_t>(qi)];
}

double PositionTable::offset(int k) const {
    return rule_ == QuantizedPositions::Centers ? (k + 0.5) / positions_ : static_cast<double>(k) / positions_;
}

PermStructure PermStructure::build(const Volume& volume, const Classification& classification, const PermSettings& s,
                                   const FitCheck& before_records) {
    PermStructure p;
    p.dims_ = volume.dims();
    const glm::ivec3 d = p.dims_;
    p.density_table_ = PositionTable(s.density_positions, s.qbm, s.positions);
    p.gradient_table_ = PositionTable(s.gradient_positions, s.qbm, s.positions);
    p.value_min_ = volume.min_value();
    p.value_range_ = std::max(volume.max_value() - volume.min_value(), 1e-20f);
    const int density_bytes = scalar_size_bytes(volume.source_type()) == 1 ? 1 : 2;
    p.density_steps_ = density_bytes == 1 ? 255.0f : 65535.0f;
    const GradientField gradients = compute_gradients(volume);
    for (const glm::vec3& g : gradients.gradients) p.gradient_max_ = glm::max(p.gradient_max_, glm::abs(g));

    // Candidates, z slice by z slice (in parallel), then numbered in storage order.
    p.index_.assign(volume.samples().size(), kNull);
    std::vector<std::vector<glm::ivec3>> per_slice(static_cast<std::size_t>(std::max(d.z - 1, 0)));
    tbb::parallel_for(0, std::max(d.z - 1, 0), [&](int z) {
        for (int y = 0; y + 1 < d.y; ++y)
            for (int x = 0; x + 1 < d.x; ++x) {
                bool candidate;
                if (s.candidates == CandidateRule::PaperOrigin) {
                    const float v = volume.at(x, y, z);
                    candidate = classification.may_be_nonzero(v, v, glm::length(gradients.at(volume.index(x, y, z))));
                } else {
                    float lo = volume.at(x, y, z), hi = lo, g = 0;
                    for (int c = 0; c < 8; ++c) {
                        const int cx = x + (c & 1), cy = y + ((c >> 1) & 1), cz = z + (c >> 2);
                        const float v = volume.at(cx, cy, cz);
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                        g = std::max(g, glm::length(gradients.at(volume.index(cx, cy, cz))));
                    }
                    candidate = classification.may_be_nonzero(lo, hi, g);
                }
                if (candidate) per_slice[static_cast<std::size_t>(z)].push_back({x, y, z});
            }
    });
    for (std::size_t z = 0; z < per_slice.size(); ++z) {
        if (s.index_bytes == 2 && per_slice[z].size() > 65535)
            throw InputError("machine configuration", "perm.index_bytes",
                             fmt::format("z slice {} holds {} candidate cells, more than 2-byte per-slice indices can number; use 4",
                                         z, per_slice[z].size()));
        for (const glm::ivec3& c : per_slice[z]) {
            p.index_[volume.index(c.x, c.y, c.z)] = static_cast<std::int32_t>(p.cell_origin_.size());
            p.cell_origin_.push_back(c);
        }
    }
    const std::size_t n = p.cell_origin_.size();
    p.memory_ = PermMemory{d, n, s.density_positions, s.gradient_positions, s.index_bytes, density_bytes};
    if (before_records) before_records(p.memory_, p.cell_origin_);

    // The records: density and gradient interpolated at each quantized position.
    const std::size_t dn = cube(s.density_positions), gn = cube(s.gradient_positions);
    p.density_.resize(n * dn);
    p.gradient_.resize(n * gn * 3);
    p.signs_.resize(n * gn);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t m) {
        const glm::ivec3 o = p.cell_origin_[m];
        float values[8];
        glm::vec3 grads[8];
        for (int c = 0; c < 8; ++c) {
            const int cx = o.x + (c & 1), cy = o.y + ((c >> 1) & 1), cz = o.z + (c >> 2);
            values[c] = volume.at(cx, cy, cz);
            grads[c] = gradients.at(volume.index(cx, cy, cz));
        }
        const auto offset = [](const PositionTable& t, std::size_t i) {
            const int n_ = t.positions();
            const int a = static_cast<int>(i % static_cast<std::size_t>(n_)), b = static_cast<int>((i / static_cast<std::size_t>(n_)) % static_cast<std::size_t>(n_)),
                      c = static_cast<int>(i / static_cast<std::size_t>(n_ * n_));
            return glm::vec3(static_cast<float>(t.offset(a)), static_cast<float>(t.offset(b)), static_cast<float>(t.offset(c)));
        };
        for (std::size_t i = 0; i < dn; ++i) {
            const float v = in_cell(values, offset(p.density_table_, i));
            p.density_[m * dn + i] = static_cast<std::uint16_t>(std::lround(std::clamp((v - p.value_min_) / p.value_range_, 0.0f, 1.0f) * p.density_steps_));
        }
        for (std::size_t i = 0; i < gn; ++i) {
            const glm::vec3 g = in_cell(grads, offset(p.gradient_table_, i));
            std::uint8_t sign = 0;
            for (int a = 0; a < 3; ++a) {
                const float top = p.gradient_max_[a];
                p.gradient_[(m * gn + i) * 3 + static_cast<std::size_t>(a)] =
                    top > 0 ? static_cast<std::uint8_t>(std::lround(std::min(std::abs(g[a]) / top, 1.0f) * 255.0f)) : 0;
                if (g[a] < 0) sign = static_cast<std::uint8_t>(sign | (1u << (2 * a)));
            }
            p.signs_[m * gn + i] = sign;
        }
    });
    return p;
}

int PermStructure::combined(const PositionTable& t, glm::vec3 fraction, std::uint64_t* carried) const {
    const int n = t.positions();
    const int x = t.index(fraction.x), y = t.index(fraction.y), z = t.index(fraction.z);
    if (carried != nullptr && (x == n || y == n || z == n)) ++*carried;
    // x + N y + N^2 z as eq. (4) writes it; a carry lands in the next axis's digit, and past the last
    // position of the record it stays on the last.
    return std::min(x + n * y + n * n * z, n * n * n - 1);
}

PermStructure::Sample PermStructure::lookup(std::uint32_t candidate, glm::vec3 fraction, std::uint64_t* carried) const {
    const std::size_t dn = cube(density_table_.positions()), gn = cube(gradient_table_.positions());
    const std::size_t di = static_cast<std::size_t>(combined(density_table_, fraction, carried));
    const std::size_t gi = static_cast<std::size_t>(combined(gradient_table_, fraction, carried));
    Sample out;
    out.value = value_min_ + static_cast<float>(density_[candidate * dn + di]) / density_steps_ * value_range_;
    const std::size_t g = candidate * gn + gi;
    for (int a = 0; a < 3; ++a) {
        const float magnitude = static_cast<float>(gradient_[g * 3 + static_cast<std::size_t>(a)]) / 255.0f * gradient_max_[a];
        out.gradient[a] = (signs_[g] >> (2 * a)) & 1u ? -magnitude : magnitude;
    }
    return out;
}

glm::vec3 PermStructure::snapped_density_fraction(glm::vec3 f) const {
    return {static_cast<float>(density_table_.offset(std::min(density_table_.index(f.x), density_table_.positions() - 1))),
            static_cast<float>(density_table_.offset(std::min(density_table_.index(f.y), density_table_.positions() - 1))),
            static_cast<float>(density_table_.offset(std::min(density_table_.index(f.z), density_table_.positions() - 1)))};
}

glm::vec3 PermStructure::snapped_gradient_fraction(glm::vec3 f) const {
    return {static_cast<float>(gradient_table_.offset(std::min(gradient_table_.index(f.x), gradient_table_.positions() - 1))),
            static_cast<float>(gradient_table_.offset(std::min(gradient_table_.index(f.y), gradient_table_.positions() - 1))),
            static_cast<float>(gradient_table_.offset(std::min(gradient_table_.index(f.z), gradient_table_.positions() - 1)))};
}

}  // namespace pp5
