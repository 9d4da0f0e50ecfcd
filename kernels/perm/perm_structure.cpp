#include "kernels/perm/perm_structure.h"

#include "scene/reference/gradient_field.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

namespace {

std::uint64_t cube(int n) {
    return static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n);
}

// Trilinear interpolation inside one cell from its eight corners (index by x + 2y + 4z).
template <class T>
T in_cell(const T (&c)[8], glm::vec3 w) {
    const auto lerp = [](const T& a, const T& b, float t) { return a + (b - a) * t; };
    const T x00 = lerp(c[0], c[1], w.x), x10 = lerp(c[2], c[3], w.x), x01 = lerp(c[4], c[5], w.x),
            x11 = lerp(c[6], c[7], w.x);
    return lerp(lerp(x00, x10, w.y), lerp(x01, x11, w.y), w.z);
}

// The volume's cells (one fewer than its voxels along each axis), numbered x fastest.
struct CellGrid {
    glm::ivec3 c;

    std::size_t size() const {
        return static_cast<std::size_t>(c.x) * static_cast<std::size_t>(c.y) * static_cast<std::size_t>(c.z);
    }
    std::size_t cell(glm::ivec3 q) const {
        return static_cast<std::size_t>(q.x) +
               static_cast<std::size_t>(c.x) *
                   (static_cast<std::size_t>(q.y) + static_cast<std::size_t>(c.y) * static_cast<std::size_t>(q.z));
    }
    glm::ivec3 coords(std::size_t i) const {
        return glm::ivec3(static_cast<int>(i % static_cast<std::size_t>(c.x)),
                          static_cast<int>((i / static_cast<std::size_t>(c.x)) % static_cast<std::size_t>(c.y)),
                          static_cast<int>(i / (static_cast<std::size_t>(c.x) * static_cast<std::size_t>(c.y))));
    }
    bool inside(glm::ivec3 q) const { return q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < c.x && q.y < c.y && q.z < c.z; }
    bool on_boundary(glm::ivec3 q) const {
        return q.x == 0 || q.y == 0 || q.z == 0 || q.x == c.x - 1 || q.y == c.y - 1 || q.z == c.z - 1;
    }
};

enum CellKind : std::uint8_t { kEmpty, kTranslucent, kOpaque };

// Each candidate cell opaque (every sample it can be read at is at least alpha_e opaque) or
// translucent; the other cells empty.
std::vector<std::uint8_t> classify_cells(const CellGrid& grid, const Volume& volume, const GradientField& gradients,
                                         const Classification& classification, const PermSettings& s,
                                         const std::vector<std::vector<glm::ivec3>>& per_slice) {
    std::vector<std::uint8_t> kind(grid.size(), kEmpty);
    const PositionTable density(s.density_positions, s.qbm, s.positions),
        gradient(s.gradient_positions, s.qbm, s.positions);
    pp5::parallel_for(std::size_t{0}, per_slice.size(), [&](std::size_t z) {
        for (const glm::ivec3& o : per_slice[z]) {
            float values[8];
            glm::vec3 grads[8];
            for (int k = 0; k < 8; ++k) {
                const glm::ivec3 v = o + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
                values[k] = volume.at(v.x, v.y, v.z);
                grads[k] = gradients.at(volume.index(v.x, v.y, v.z));
            }
            // The least gradient magnitude any sample here reads, then the least opacity: Levoy's
            // functions do not fall as the gradient grows, so that bounds every sample's opacity.
            float least_gradient = 1e30f;
            const int gn = gradient.positions(), dn = density.positions();
            for (int i = 0; i < gn * gn * gn; ++i) {
                const glm::vec3 w(static_cast<float>(gradient.offset(i % gn)),
                                  static_cast<float>(gradient.offset((i / gn) % gn)),
                                  static_cast<float>(gradient.offset(i / (gn * gn))));
                least_gradient = std::min(least_gradient, glm::length(in_cell(grads, w)));
            }
            float least = 1;
            for (int i = 0; i < dn * dn * dn && least >= s.reduction_opacity; ++i) {
                const glm::vec3 w(static_cast<float>(density.offset(i % dn)),
                                  static_cast<float>(density.offset((i / dn) % dn)),
                                  static_cast<float>(density.offset(i / (dn * dn))));
                least = std::min(least, classification.opacity(in_cell(values, w), least_gradient));
            }
            kind[grid.cell(o)] = least >= s.reduction_opacity ? kOpaque : kTranslucent;
        }
    });
    return kind;
}

constexpr std::int32_t kUnreached = -1;

// The sources at depth 0 (translucent cells, empty cells on the boundary and the empty cells they reach
// 6-connected through empty cells) and the opaque boundary cells at depth 1, in the order found.
std::vector<std::size_t> seed_sources(const CellGrid& grid, const std::vector<std::uint8_t>& kind,
                                      std::vector<std::int32_t>& depth) {
    std::vector<std::size_t> frontier;
    std::vector<std::size_t> open;  // empty cells reached from the outside
    for (int z = 0; z < grid.c.z; ++z)
        for (int y = 0; y < grid.c.y; ++y)
            for (int x = 0; x < grid.c.x; ++x) {
                const bool boundary = grid.on_boundary({x, y, z});
                const std::size_t i = grid.cell({x, y, z});
                if (kind[i] == kTranslucent || (boundary && kind[i] == kEmpty)) {
                    depth[i] = 0;
                    if (kind[i] == kEmpty) open.push_back(i);
                    frontier.push_back(i);
                } else if (boundary && kind[i] == kOpaque) {
                    depth[i] = 1;  // next to the outside
                    frontier.push_back(i);
                }
            }
    for (std::size_t k = 0; k < open.size(); ++k) {
        const glm::ivec3 q = grid.coords(open[k]);
        for (const glm::ivec3 step : {glm::ivec3(1, 0, 0), glm::ivec3(-1, 0, 0), glm::ivec3(0, 1, 0),
                                      glm::ivec3(0, -1, 0), glm::ivec3(0, 0, 1), glm::ivec3(0, 0, -1)}) {
            const glm::ivec3 n = q + step;
            if (!grid.inside(n)) continue;
            const std::size_t i = grid.cell(n);
            if (kind[i] != kEmpty || depth[i] != kUnreached) continue;
            depth[i] = 0;
            open.push_back(i);
            frontier.push_back(i);
        }
    }
    return frontier;
}

// Each cell's depth in 26-connected steps through opaque cells from the nearest source; kUnreached
// for cells no ray reaches (cavities enclosed by opaque cells are not sources).
std::vector<std::int32_t> depths_from_sources(const CellGrid& grid, const std::vector<std::uint8_t>& kind) {
    std::vector<std::int32_t> depth(grid.size(), kUnreached);
    std::vector<std::size_t> frontier = seed_sources(grid, kind, depth);
    // Each source's neighbours first (a stable order keeps it deterministic).
    std::sort(frontier.begin(), frontier.end(),
              [&](std::size_t a, std::size_t b) { return depth[a] != depth[b] ? depth[a] < depth[b] : a < b; });
    for (std::size_t k = 0; k < frontier.size(); ++k) {
        const std::size_t from = frontier[k];
        const glm::ivec3 q = grid.coords(from);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const glm::ivec3 n = q + glm::ivec3(dx, dy, dz);
                    if (!grid.inside(n)) continue;
                    const std::size_t i = grid.cell(n);
                    if (kind[i] != kOpaque || depth[i] != kUnreached) continue;
                    depth[i] = depth[from] + 1;
                    frontier.push_back(i);
                }
    }
    return depth;
}

// Section 5's reduction, for views from outside the volume: a ray that reaches a cell has crossed every
// cell between it and the outside, so a candidate more than t_e cells (in 26-connected steps) inside
// cells whose every sample is at least alpha_e opaque is never reached before the ray terminates.
// Sources are the outside, the cells connected to it through non-candidates, and every candidate that
// is not opaque (rays pass through those); cavities enclosed by opaque cells are not sources.
void reduce(const Volume& volume, const GradientField& gradients, const Classification& classification,
            const PermSettings& s, std::vector<std::vector<glm::ivec3>>& per_slice) {
    const CellGrid grid{volume.dims() - 1};
    const std::vector<std::uint8_t> kind = classify_cells(grid, volume, gradients, classification, s, per_slice);
    const std::vector<std::int32_t> depth = depths_from_sources(grid, kind);
    for (auto& slice : per_slice)
        slice.erase(std::remove_if(slice.begin(), slice.end(),
                                   [&](const glm::ivec3& o) {
                                       const std::int32_t d = depth[grid.cell(o)];
                                       return d == kUnreached || d > s.reduction_cells;
                                   }),
                    slice.end());
}

// The candidate cells, z slice by z slice (in parallel): those whose origin voxel may be visible
// (the paper's rule), or any of whose corners may be.
std::vector<std::vector<glm::ivec3>> find_candidates(const Volume& volume, const GradientField& gradients,
                                                     const Classification& classification, const PermSettings& s) {
    const glm::ivec3 d = volume.dims();
    std::vector<std::vector<glm::ivec3>> per_slice(static_cast<std::size_t>(std::max(d.z - 1, 0)));
    pp5::parallel_for(0, std::max(d.z - 1, 0), [&](int z) {
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
    return per_slice;
}

// std::lround as the records use it, without the call into libm. For the values they quantize (0 to
// 65535) x minus its whole part is exact, so comparing it with one half rounds halves away from zero as
// lround does. NaN (a volume spanning float's whole range) gives 0: lround's LONG_MIN narrowed to a
// record's width.
long nearest_integer(float x) {
    if (!(x >= 0.0f)) return 0;
    const auto whole = static_cast<long>(x);
    return whole + (x - static_cast<float>(whole) >= 0.5f ? 1 : 0);
}

// A quantized position's offset within its cell, for position i of a table's N^3.
glm::vec3 position_offset(const PositionTable& t, std::size_t i) {
    const int n = t.positions();
    const int a = static_cast<int>(i % static_cast<std::size_t>(n)),
              b = static_cast<int>((i / static_cast<std::size_t>(n)) % static_cast<std::size_t>(n)),
              c = static_cast<int>(i / static_cast<std::size_t>(n * n));
    return glm::vec3(static_cast<float>(t.offset(a)), static_cast<float>(t.offset(b)), static_cast<float>(t.offset(c)));
}

}  // namespace

std::uint64_t PermMemory::index_volume_bytes() const {
    return static_cast<std::uint64_t>(dims.x) * static_cast<std::uint64_t>(dims.y) *
           static_cast<std::uint64_t>(dims.z) * static_cast<std::uint64_t>(index_bytes);
}

std::uint64_t PermMemory::summed_table_bytes() const {
    return index_bytes == 2 ? 4 * static_cast<std::uint64_t>(dims.z) : 0;
}

std::uint64_t PermMemory::record_bytes() const {
    return cube(density_positions) * static_cast<std::uint64_t>(density_bytes) +
           cube(gradient_positions) * static_cast<std::uint64_t>(3 * kGradientBytes + kSignBytes);
}

std::uint64_t PermMemory::total_bytes() const {
    return index_volume_bytes() + summed_table_bytes() + candidates * record_bytes();
}

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
    p.density_table_ = PositionTable(s.density_positions, s.qbm, s.positions);
    p.gradient_table_ = PositionTable(s.gradient_positions, s.qbm, s.positions);
    p.value_min_ = volume.min_value();
    p.value_range_ = std::max(volume.max_value() - volume.min_value(), 1e-20f);
    p.integer_values_ = is_integer_type(volume.source_type());
    const int density_bytes = scalar_size_bytes(volume.source_type()) == 1 ? 1 : 2;
    p.density_steps_ = density_bytes == 1 ? 255.0f : 65535.0f;
    const GradientField gradients = compute_gradients(volume);
    for (const glm::vec3& g : gradients.gradients) p.gradient_max_ = glm::max(p.gradient_max_, glm::abs(g));

    std::vector<std::vector<glm::ivec3>> per_slice = find_candidates(volume, gradients, classification, s);
    for (const auto& slice : per_slice) p.unreduced_ += slice.size();
    if (s.reduction_cells > 0) reduce(volume, gradients, classification, s, per_slice);
    p.number_candidates(volume, per_slice, s.index_bytes);
    p.memory_ = PermMemory{p.dims_,       p.cell_origin_.size(), s.density_positions, s.gradient_positions,
                           s.index_bytes, density_bytes};
    if (before_records) before_records(p.memory_, p.cell_origin_);
    p.fill_records(volume, gradients);
    return p;
}

void PermStructure::number_candidates(const Volume& volume, const std::vector<std::vector<glm::ivec3>>& per_slice,
                                      int index_bytes) {
    index_.assign(volume.samples().size(), kNull);
    for (std::size_t z = 0; z < per_slice.size(); ++z) {
        if (index_bytes == 2 && per_slice[z].size() > 65535)
            reject_field(
                "perm.index_bytes",
                fmt::format("z slice {} holds {} candidate cells, more than 2-byte per-slice indices can number; use 4",
                            z, per_slice[z].size()));
        for (const glm::ivec3& c : per_slice[z]) {
            index_[volume.index(c.x, c.y, c.z)] = static_cast<std::int32_t>(cell_origin_.size());
            cell_origin_.push_back(c);
        }
    }
}

void PermStructure::fill_records(const Volume& volume, const GradientField& gradients) {
    const std::size_t n = cell_origin_.size();
    const std::size_t dn = cube(memory_.density_positions), gn = cube(memory_.gradient_positions);
    // Every record places its positions alike: their offsets within the cell, once for all.
    const auto offsets = [](const PositionTable& table, std::size_t count) {
        std::vector<glm::vec3> at(count);
        for (std::size_t i = 0; i < count; ++i) at[i] = position_offset(table, i);
        return at;
    };
    const std::vector<glm::vec3> density_offsets = offsets(density_table_, dn),
                                 gradient_offsets = offsets(gradient_table_, gn);
    density_ = std::make_unique_for_overwrite<std::uint16_t[]>(n * dn);
    gradient_ = std::make_unique_for_overwrite<std::uint8_t[]>(n * gn * 3);
    signs_ = std::make_unique_for_overwrite<std::uint8_t[]>(n * gn);
    pp5::parallel_for(std::size_t{0}, n, [&](std::size_t m) {
        const glm::ivec3 o = cell_origin_[m];
        float values[8];
        glm::vec3 grads[8];
        for (int c = 0; c < 8; ++c) {
            const int cx = o.x + (c & 1), cy = o.y + ((c >> 1) & 1), cz = o.z + (c >> 2);
            values[c] = volume.at(cx, cy, cz);
            grads[c] = gradients.at(volume.index(cx, cy, cz));
        }
        for (std::size_t i = 0; i < dn; ++i) {
            const float v = in_cell(values, density_offsets[i]);
            density_[m * dn + i] = static_cast<std::uint16_t>(
                nearest_integer(std::clamp((v - value_min_) / value_range_, 0.0f, 1.0f) * density_steps_));
        }
        for (std::size_t i = 0; i < gn; ++i) {
            const glm::vec3 g = in_cell(grads, gradient_offsets[i]);
            std::uint8_t sign = 0;
            for (int a = 0; a < 3; ++a) {
                const float top = gradient_max_[a];
                gradient_[(m * gn + i) * 3 + static_cast<std::size_t>(a)] =
                    top > 0 ? static_cast<std::uint8_t>(nearest_integer(std::min(std::abs(g[a]) / top, 1.0f) * 255.0f))
                            : 0;
                if (g[a] < 0) sign = static_cast<std::uint8_t>(sign | (1u << (2 * a)));
            }
            signs_[m * gn + i] = sign;
        }
    });
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
    return decode(candidate, static_cast<std::size_t>(combined(density_table_, fraction, carried)),
                  static_cast<std::size_t>(combined(gradient_table_, fraction, carried)));
}

PermStructure::Sample PermStructure::at_density_position(std::uint32_t candidate, int position) const {
    const int n = density_table_.positions();
    const glm::vec3 where(static_cast<float>(density_table_.offset(position % n)),
                          static_cast<float>(density_table_.offset((position / n) % n)),
                          static_cast<float>(density_table_.offset(position / (n * n))));
    return decode(candidate, static_cast<std::size_t>(position),
                  static_cast<std::size_t>(combined(gradient_table_, where, nullptr)));
}

PermStructure::Sample PermStructure::decode(std::uint32_t candidate, std::size_t di, std::size_t gi) const {
    const std::size_t gn = cube(gradient_table_.positions());
    Sample out;
    out.value = density_at(candidate, static_cast<int>(di));
    const std::size_t g = candidate * gn + gi;
    for (int a = 0; a < 3; ++a) {
        const float magnitude =
            static_cast<float>(gradient_[g * 3 + static_cast<std::size_t>(a)]) / 255.0f * gradient_max_[a];
        out.gradient[a] = (signs_[g] >> (2 * a)) & 1u ? -magnitude : magnitude;
    }
    return out;
}

glm::vec3 PermStructure::snapped_density_fraction(glm::vec3 f) const {
    return {
        static_cast<float>(density_table_.offset(std::min(density_table_.index(f.x), density_table_.positions() - 1))),
        static_cast<float>(density_table_.offset(std::min(density_table_.index(f.y), density_table_.positions() - 1))),
        static_cast<float>(density_table_.offset(std::min(density_table_.index(f.z), density_table_.positions() - 1)))};
}

glm::vec3 PermStructure::snapped_gradient_fraction(glm::vec3 f) const {
    return {static_cast<float>(
                gradient_table_.offset(std::min(gradient_table_.index(f.x), gradient_table_.positions() - 1))),
            static_cast<float>(
                gradient_table_.offset(std::min(gradient_table_.index(f.y), gradient_table_.positions() - 1))),
            static_cast<float>(
                gradient_table_.offset(std::min(gradient_table_.index(f.z), gradient_table_.positions() - 1)))};
}

}  // namespace pp5
