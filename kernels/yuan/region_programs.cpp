#include "kernels/yuan/region_programs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pp5 {

namespace {

constexpr int kShift = RegionFormat::kCoefficientShift;
constexpr int kQuad = RegionFormat::kQuadraticBits;
constexpr int kExactBits = 34;  // N and M of the exact index: non-negative, below 2^34 over a region
constexpr int kIndexBits = RegionFormat::kIndexBits;
constexpr std::int64_t kIndexOne = std::int64_t{1} << kIndexBits;
constexpr int kDividedBits = kIndexBits + 1;

// The region state every program allocates first, in this order, so that it stays in the same fields.
struct RegionState {
    PpField color[3];
    PpField alpha;
    PpField sheet[4];
};

RegionState allocate_state(PpProgramBuilder& b, const RegionFormat& f) {
    RegionState s;
    const char* channels[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) s.color[c] = b.alloc(std::string("C_") + channels[c], f.accumulator_bits, false);
    s.alpha = b.alloc("A", f.accumulator_bits, false);
    const char* sheet[4] = {"S_red", "S_green", "S_blue", "S_opacity"};
    for (int c = 0; c < 4; ++c) s.sheet[c] = b.alloc(sheet[c], f.sheet_field_bits(), false);
    return s;
}

// field = min(field + value, limit), the value's fields released.
void accumulate(PpProgramBuilder& b, PpField field, PpField value, std::int64_t limit) {
    const PpField sum = b.add("sum", field, value);
    b.release(value);
    const PpField clamped = b.min_const("clamped", sum, limit);
    b.release(sum);
    b.assign(field, clamped);
    b.release(clamped);
}

std::int64_t limit_of(int bits) { return (std::int64_t{1} << bits) - 1; }

}  // namespace

RegionPrograms::RegionPrograms(const RegionFormat& format, SplatIndexMode mode, SplatBlend blend, int local_memory_bits)
    : format_(format), mode_(mode), blend_(blend), local_memory_bits_(local_memory_bits) {}

PpProgram RegionPrograms::splat(const PpTable& table) const {
    const RegionFormat& f = format_;
    PpProgramBuilder b(std::string("yuan splat ") + (mode_ == SplatIndexMode::Exact ? "exact " : "") +
                           (blend_ == SplatBlend::Over ? "over" : "sheet"),
                       local_memory_bits_);
    const RegionState s = allocate_state(b, f);
    b.enable_all();
    int constants = 1;
    PpField index;
    if (mode_ == SplatIndexMode::Affine) {
        const PpField q = b.qee("i2", 0, kQuad, true, kShift);
        b.enable_if(q, PpCompare::Less, kIndexOne);
        const PpField low = b.max_const("i2_low", q, 0);
        b.release(q);
        index = b.min_const("i2_clamped", low, kIndexOne - 1);
        b.release(low);
    } else {
        const PpField n = b.qee("N", 0, kExactBits, false, kShift);
        const PpField m = b.qee("M", 1, kExactBits, false, kShift);
        const PpField d2 = b.div("d2", n, m, kIndexBits, kDividedBits);
        b.release(n);
        b.release(m);
        b.enable_if(d2, PpCompare::Less, kIndexOne);
        index = b.min_const("d2_clamped", d2, kIndexOne - 1);
        b.release(d2);
        constants = 2;
    }
    const PpField row = b.move("row", index, kIndexBits - f.table_bits);
    b.release(index);
    const PpField weight = b.lookup("w", row, table, f.accumulator_bits, false);
    b.release(row);
    const PpField opacity = b.qee("alpha", constants, f.accumulator_bits + 1, false, 0);
    const PpField covered = b.mul("alpha_w", weight, opacity, f.accumulator_bits);
    b.release(weight);
    b.release(opacity);
    if (blend_ == SplatBlend::Over) {
        const PpField one = b.set_const("one", f.one());
        const PpField clear = b.sub("1-A", one, s.alpha);
        b.release(one);
        const PpField share = b.mul("share", clear, covered, f.accumulator_bits);
        b.release(clear);
        b.release(covered);
        for (int c = 0; c < 3; ++c) {
            const PpField color = b.qee("c", constants + 1 + c, f.accumulator_bits + 1, false, 0);
            const PpField add = b.mul("dC", share, color, f.accumulator_bits);
            b.release(color);
            accumulate(b, s.color[c], add, f.one() - 1);
        }
        accumulate(b, s.alpha, share, f.one() - 1);
    } else {
        const std::int64_t top = limit_of(f.sheet_field_bits());
        for (int c = 0; c < 3; ++c) {
            const PpField color = b.qee("c", constants + 1 + c, f.accumulator_bits + 1, false, 0);
            const PpField add = b.mul("dS", covered, color, f.accumulator_bits - 2);
            b.release(color);
            accumulate(b, s.sheet[c], add, top);
        }
        accumulate(b, s.sheet[3], b.mul_const("dS_alpha", covered, 4), top);
        b.release(covered);
    }
    return b.finish();
}

PpProgram RegionPrograms::point() const {
    const RegionFormat& f = format_;
    PpProgramBuilder b("yuan point", local_memory_bits_);
    const RegionState s = allocate_state(b, f);
    const std::int64_t top = limit_of(f.sheet_field_bits());
    b.enable_all();
    // The opacity weight first: where it is positive the point reaches the pixel.
    const PpField weight = b.qee("v_alpha", 3, kQuad, true, kShift);
    b.enable_if(weight, PpCompare::Greater, 0);
    for (const int c : {3, 0, 1, 2}) {
        const PpField v = c == 3 ? weight : b.qee("v", c, kQuad, true, kShift);
        const PpField low = b.max_const("v_low", v, 0);
        b.release(v);
        const PpField clamped = b.min_const("v_clamped", low, top);
        b.release(low);
        accumulate(b, s.sheet[c], clamped, top);
    }
    return b.finish();
}

PpProgram RegionPrograms::sheet_add() const {
    const RegionFormat& f = format_;
    PpProgramBuilder b("yuan sheet add", local_memory_bits_);
    const RegionState s = allocate_state(b, f);
    const std::int64_t top = limit_of(f.sheet_field_bits());
    // The controller has written the block's four words per pixel here.
    PpField staged[4];
    for (int c = 0; c < 4; ++c) staged[c] = b.alloc("staged", f.sheet_field_bits(), false);
    b.enable_all();
    for (int c = 0; c < 4; ++c) accumulate(b, s.sheet[c], staged[c], top);
    return b.finish();
}

PpProgram RegionPrograms::band_composite() const {
    const RegionFormat& f = format_;
    PpProgramBuilder b("yuan band composite", local_memory_bits_);
    const RegionState s = allocate_state(b, f);
    b.enable_all();
    const PpField one = b.set_const("one", f.one());
    const PpField clear = b.sub("1-A", one, s.alpha);
    b.release(one);
    for (int c = 0; c < 4; ++c) {
        const PpField level = b.min_const("S_clamped", s.sheet[c], f.sheet_one());
        const PpField add = b.mul("dC", clear, level, f.sheet_bits());
        b.release(level);
        accumulate(b, c == 3 ? s.alpha : s.color[c], add, f.one() - 1);
    }
    b.release(clear);
    for (int c = 0; c < 4; ++c) b.assign_const(s.sheet[c], 0);
    return b.finish();
}

PpProgram RegionPrograms::readout() const {
    const RegionFormat& f = format_;
    PpProgramBuilder b("yuan readout", local_memory_bits_);
    const RegionState s = allocate_state(b, f);
    b.enable_all();
    // Eight bits a channel for the frame buffer's port.
    for (int c = 0; c < 3; ++c) b.release(b.move("out", s.color[c], f.accumulator_bits - 8));
    return b.finish();
}

RegionPixels::RegionPixels(int c, int r) : columns(c), rows(r) {
    const auto n = static_cast<std::size_t>(c) * static_cast<std::size_t>(r);
    for (auto& v : color) v.assign(n, 0);
    alpha.assign(n, 0);
    for (auto& v : sheet) v.assign(n, 0);
}

std::uint32_t draw_splat(RegionPixels& region, const SplatDraw& splat, const PpTable& table, const RegionFormat& f,
                         SplatIndexMode mode, SplatBlend blend) {
    const int constants = mode == SplatIndexMode::Affine ? 1 : 2;
    const std::int64_t opacity =
        qee_value(splat.expressions[static_cast<std::size_t>(constants)], 0, 0, 0, f.accumulator_bits + 1, false);
    std::int64_t color[3];
    for (int c = 0; c < 3; ++c)
        color[c] = qee_value(splat.expressions[static_cast<std::size_t>(constants + 1 + c)], 0, 0, 0,
                             f.accumulator_bits + 1, false);
    const std::int64_t top = limit_of(f.sheet_field_bits());
    const int table_shift = kIndexBits - f.table_bits;
    std::uint32_t changed = 0;
    for (int y = std::max(splat.y0, 0); y <= std::min(splat.y1, region.rows - 1); ++y) {
        for (int x = std::max(splat.x0, 0); x <= std::min(splat.x1, region.columns - 1); ++x) {
            std::int64_t index;
            if (mode == SplatIndexMode::Affine) {
                const std::int64_t q = qee_value(splat.expressions[0], x, y, kShift, kQuad, true);
                if (!(q < kIndexOne)) continue;
                index = std::min(std::max<std::int64_t>(q, 0), kIndexOne - 1);
            } else {
                const std::int64_t n = qee_value(splat.expressions[0], x, y, kShift, kExactBits, false);
                const std::int64_t m = qee_value(splat.expressions[1], x, y, kShift, kExactBits, false);
                const std::int64_t most = limit_of(kDividedBits);
                const std::int64_t d2 = m > 0 && n <= (std::numeric_limits<std::int64_t>::max() >> kIndexBits)
                                            ? std::min((n << kIndexBits) / m, most)
                                            : most;
                if (!(d2 < kIndexOne)) continue;
                index = std::min(d2, kIndexOne - 1);
            }
            const std::int64_t weight = table.entries[static_cast<std::size_t>(index >> table_shift)];
            const std::int64_t covered = (weight * opacity) >> f.accumulator_bits;
            const std::size_t p = region.index(x, y);
            ++changed;
            if (blend == SplatBlend::Over) {
                const std::int64_t share = ((f.one() - region.alpha[p]) * covered) >> f.accumulator_bits;
                for (int c = 0; c < 3; ++c)
                    region.color[c][p] = static_cast<std::int32_t>(
                        std::min(region.color[c][p] + ((share * color[c]) >> f.accumulator_bits), f.one() - 1));
                region.alpha[p] = static_cast<std::int32_t>(std::min(region.alpha[p] + share, f.one() - 1));
            } else {
                for (int c = 0; c < 3; ++c)
                    region.sheet[c][p] = static_cast<std::int32_t>(
                        std::min(region.sheet[c][p] + ((covered * color[c]) >> (f.accumulator_bits - 2)), top));
                region.sheet[3][p] = static_cast<std::int32_t>(std::min(region.sheet[3][p] + covered * 4, top));
            }
        }
    }
    return changed;
}

namespace {

// Calls visit(x, y, weights) for each pixel of the point's box within [cx0, cx1] x [cy0, cy1] that the
// point reaches, with its four clamped weights.
template <class Visit>
void for_each_point_pixel(const PointDraw& point, const RegionFormat& f, int cx0, int cy0, int cx1, int cy1,
                          Visit&& visit) {
    const std::int64_t top = limit_of(f.sheet_field_bits());
    for (int y = std::max(point.y0, cy0); y <= std::min(point.y1, cy1); ++y) {
        for (int x = std::max(point.x0, cx0); x <= std::min(point.x1, cx1); ++x) {
            const std::int64_t opacity = qee_value(point.expressions[3], x, y, kShift, kQuad, true);
            if (!(opacity > 0)) continue;
            std::array<std::int32_t, 4> v;
            for (int c = 0; c < 4; ++c) {
                const std::int64_t raw =
                    c == 3 ? opacity
                           : qee_value(point.expressions[static_cast<std::size_t>(c)], x, y, kShift, kQuad, true);
                v[static_cast<std::size_t>(c)] =
                    static_cast<std::int32_t>(std::min(std::max<std::int64_t>(raw, 0), top));
            }
            visit(x, y, v);
        }
    }
}

// cell = min(cell + v, top), channel by channel.
void add_clamped(std::array<std::int32_t, 4>& cell, const std::array<std::int32_t, 4>& v, std::int64_t top) {
    for (std::size_t c = 0; c < 4; ++c)
        cell[c] = static_cast<std::int32_t>(std::min<std::int64_t>(cell[c] + v[c], top));
}

}  // namespace

std::uint32_t draw_point(RegionPixels& region, const PointDraw& point, const RegionFormat& f) {
    const std::int64_t top = limit_of(f.sheet_field_bits());
    std::uint32_t changed = 0;
    for_each_point_pixel(point, f, 0, 0, region.columns - 1, region.rows - 1,
                         [&](int x, int y, const std::array<std::int32_t, 4>& v) {
                             const std::size_t p = region.index(x, y);
                             for (int c = 0; c < 4; ++c)
                                 region.sheet[c][p] = static_cast<std::int32_t>(
                                     std::min<std::int64_t>(region.sheet[c][p] + v[static_cast<std::size_t>(c)], top));
                             ++changed;
                         });
    return changed;
}

std::uint32_t filter_point(const PointDraw& point, const RegionFormat& f, int x0, int y0, int x1, int y1,
                           std::vector<std::array<std::int32_t, 4>>& block) {
    const std::int64_t top = limit_of(f.sheet_field_bits());
    const auto w = static_cast<std::size_t>(x1 - x0 + 1);
    std::uint32_t reached = 0;
    for_each_point_pixel(point, f, x0, y0, x1, y1, [&](int x, int y, const std::array<std::int32_t, 4>& v) {
        add_clamped(block[static_cast<std::size_t>(y - y0) * w + static_cast<std::size_t>(x - x0)], v, top);
        ++reached;
    });
    return reached;
}

void add_sheet_block(RegionPixels& region, int x0, int y0, int x1, int y1,
                     const std::vector<std::array<std::int32_t, 4>>& block, const RegionFormat& f) {
    const std::int64_t top = limit_of(f.sheet_field_bits());
    const int w = x1 - x0 + 1;
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const auto& v = block[static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x - x0)];
            const std::size_t p = region.index(x, y);
            for (int c = 0; c < 4; ++c)
                region.sheet[c][p] = static_cast<std::int32_t>(
                    std::min<std::int64_t>(region.sheet[c][p] + v[static_cast<std::size_t>(c)], top));
        }
    }
}

std::uint32_t composite_band(RegionPixels& region, const RegionFormat& f) {
    std::uint32_t held = 0;
    const std::size_t n = region.alpha.size();
    for (std::size_t p = 0; p < n; ++p) {
        if ((region.sheet[0][p] | region.sheet[1][p] | region.sheet[2][p] | region.sheet[3][p]) == 0) continue;
        ++held;
        const std::int64_t clear = f.one() - region.alpha[p];
        for (int c = 0; c < 4; ++c) {
            const std::int64_t level = std::min<std::int64_t>(region.sheet[c][p], f.sheet_one());
            std::int32_t& target = c == 3 ? region.alpha[p] : region.color[c][p];
            target = static_cast<std::int32_t>(std::min(target + ((clear * level) >> f.sheet_bits()), f.one() - 1));
            region.sheet[c][p] = 0;
        }
    }
    return held;
}

}  // namespace pp5
