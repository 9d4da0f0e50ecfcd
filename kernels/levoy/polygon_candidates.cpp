#include "kernels/levoy/polygon_candidates.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace pp5 {

namespace {

// Wide enough for D x + E y + F with any 64-bit coefficients at any PP.
__extension__ typedef __int128 Wide;

// floor(n / d) and ceil(n / d) for d != 0.
std::int64_t floor_div(std::int64_t n, std::int64_t d) {
    const std::int64_t q = n / d;
    return (q * d != n && ((n < 0) != (d < 0))) ? q - 1 : q;
}
std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }

// The PPs at which some plane test D x + E y + F_j, j = 0..J-1, may come within half a voxel: the
// translations move the plane, so the expressions share D and E and differ in F.
struct PlaneBand {
    std::int64_t d = 0, e = 0;
    std::int64_t low = 0, high = 0;  // D x + E y in [low, high]: [-H - max F, H - min F]
    bool whole = false;              // some value might wrap in its field: every PP may pass

    // The columns [first, last] of `row` in the band; empty when first > last.
    std::pair<int, int> columns(int row, int columns) const {
        if (whole) return {0, columns - 1};
        // low - E y <= D x <= high - E y, for x in [0, columns).
        const std::int64_t from = low - e * row, to = high - e * row;
        return clamped(from, to, d, columns);
    }
    // The rows [first, last] whose span of columns, taken as real, meets the band.
    std::pair<int, int> rows(int columns, int rows) const {
        if (whole) return {0, rows - 1};
        const std::int64_t along_row = d * (columns - 1);
        return clamped(low - std::max<std::int64_t>(0, along_row), high - std::min<std::int64_t>(0, along_row), e,
                       rows);
    }

private:
    // The integers t in [0, count) with from <= k t <= to; empty when first > last.
    static std::pair<int, int> clamped(std::int64_t from, std::int64_t to, std::int64_t k, int count) {
        if (k == 0) return (from <= 0 && 0 <= to) ? std::pair{0, count - 1} : std::pair{1, 0};
        const std::int64_t first = k > 0 ? ceil_div(from, k) : ceil_div(to, k);
        const std::int64_t last = k > 0 ? floor_div(to, k) : floor_div(from, k);
        return {static_cast<int>(std::clamp<std::int64_t>(first, 0, count)),
                static_cast<int>(std::clamp<std::int64_t>(last, -1, count - 1))};
    }
};

}  // namespace

void polygon_candidates(const PreparedPolygon& polygon, int samples, const PpProgram& program,
                        std::span<const QeeCoefficients> expressions, const PpArrayShape& shape,
                        std::vector<int>& out) {
    out.clear();
    // The plane tests: translation j's is expression j (1 + edges) (polygon_expressions' order), and
    // the QEE writes it to a field whose width bounds its values.
    const int per_sample = 1 + static_cast<int>(polygon.edge_normals.size());
    PlaneBand band;
    bool any = false;
    std::int64_t least_f = 0, most_f = 0;
    std::int64_t field_min = std::numeric_limits<std::int64_t>::min();
    std::int64_t field_max = std::numeric_limits<std::int64_t>::max();
    for (const PpInstruction& in : program.instructions) {
        if (in.op != PpOp::Qee || in.expression % per_sample != 0 || in.expression >= samples * per_sample) continue;
        if (static_cast<std::size_t>(in.expression) >= expressions.size())
            throw std::invalid_argument("polygon_candidates: fewer expressions than the program evaluates");
        const QeeCoefficients& q = expressions[static_cast<std::size_t>(in.expression)];
        if (q.a != 0 || q.b != 0 || q.c != 0 || (any && (q.d != band.d || q.e != band.e)))
            throw std::logic_error("polygon_candidates: the plane tests are one plane, translated");
        const PpField& field = program.fields[static_cast<std::size_t>(in.dst)];
        field_min = std::max(field_min, field.min_value());
        field_max = std::min(field_max, field.max_value());
        band.d = q.d;
        band.e = q.e;
        least_f = any ? std::min(least_f, q.f) : q.f;
        most_f = any ? std::max(most_f, q.f) : q.f;
        any = true;
    }
    if (!any) return;
    // A value past its field wraps to anything, so might pass: where one could, every PP is a candidate.
    // Values are linear in x, y and F, so the slot's corners at the least and most F bound them all.
    const Wide along_row = static_cast<Wide>(band.d) * (shape.columns - 1);
    const Wide down = static_cast<Wide>(band.e) * (shape.rows - 1);
    for (const Wide f : {static_cast<Wide>(least_f), static_cast<Wide>(most_f)})
        for (const Wide corner : {f, f + along_row, f + down, f + along_row + down})
            band.whole = band.whole || corner < field_min || corner > field_max;
    if (!band.whole) {
        // Every value fits its field (48 bits at most): the band's arithmetic stays in 64 bits.
        band.low = -kPolygonSheetHalfWidth - most_f;
        band.high = kPolygonSheetHalfWidth - least_f;
    }
    const auto [first_row, last_row] = band.rows(shape.columns, shape.rows);
    for (int row = first_row; row <= last_row; ++row) {
        const auto [first, last] = band.columns(row, shape.columns);
        for (int column = first; column <= last; ++column) out.push_back(column + row * shape.columns);
    }
}

}  // namespace pp5
