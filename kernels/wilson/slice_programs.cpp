#include "kernels/wilson/slice_programs.h"

#include <algorithm>
#include <utility>

namespace pp5 {

namespace {

constexpr int kShift = kQeeCoefficientShift;
constexpr int kQuad = kQeeResultBits;
constexpr std::int64_t kIndexTop = (std::int64_t{1} << SliceFormat::kIndexBits) - 1;
// Result widths: wide enough that no pixel of a region wraps into a valid index (see setup()).
constexpr int kParallelIndexBits = 20;
constexpr int kPerspectiveWBits = 24;
constexpr int kPerspectiveIndexBits = 36;
constexpr int kChannelBits = 16;  // a quad's channel near its cell: within [0, 1] up to rounding (this holds [-8, 8))

struct SliceState {
    PpField color[3];
    PpField alpha;
    PpField slice[4];
    PpField key;
};

SliceState allocate_state(PpProgramBuilder& b, const SliceFormat& f) {
    SliceState s;
    const char* channels[3] = {"C_red", "C_green", "C_blue"};
    for (int c = 0; c < 3; ++c) s.color[c] = b.alloc(channels[c], f.accumulator_bits, false);
    s.alpha = b.alloc("A", f.accumulator_bits, false);
    const char* slice[4] = {"S_red", "S_green", "S_blue", "S_opacity"};
    for (int c = 0; c < 4; ++c) s.slice[c] = b.alloc(slice[c], f.accumulator_bits, false);
    s.key = b.alloc("K", SliceFormat::kKeyBits, false);
    return s;
}

// field = min(value, top), the value's field released.
void assign_clamped(PpProgramBuilder& b, PpField field, PpField value, std::int64_t top) {
    const PpField clamped = b.min_const("clamped", value, top);
    b.release(value);
    b.assign(field, clamped);
    b.release(clamped);
}

// Channel by channel, target = min(front + target (1 - a), top): "over" with `clear` = 1 - a, which is
// released after. front(c) gives channel c's premultiplied value and whether this releases it.
template <class Front>
void composite_over(PpProgramBuilder& b, const SliceState& s, PpField clear, const SliceFormat& f, Front&& front) {
    for (int c = 0; c < 4; ++c) {
        const PpField target = c == 3 ? s.alpha : s.color[c];
        const PpField behind = b.mul("behind", target, clear, f.accumulator_bits);
        const auto [value, owned] = front(c);
        const PpField sum = b.add("sum", value, behind);
        if (owned) b.release(value);
        b.release(behind);
        assign_clamped(b, target, sum, f.top());
    }
    b.release(clear);
}

// Where (x - x0)(x1 - x) >= 0: the integers x0..x1, as a quadratic of the region-local position.
QeeCoefficients span_test(int lo, int hi, bool along_x) {
    const std::int64_t sum = static_cast<std::int64_t>(lo) + hi, product = static_cast<std::int64_t>(lo) * hi;
    return along_x ? QeeCoefficients{-1, 0, 0, sum, 0, -product} : QeeCoefficients{0, 0, -1, 0, sum, -product};
}

// target = min(add + (target (1 - a)) >> bits, top): "over" of a premultiplied value.
std::int32_t over(std::int64_t target, std::int64_t add, std::int64_t one_minus_alpha, const SliceFormat& f) {
    return static_cast<std::int32_t>(std::min(add + ((target * one_minus_alpha) >> f.accumulator_bits), f.top()));
}

}  // namespace

SlicePrograms::SlicePrograms(const SliceFormat& format, int local_memory_bits)
    : format_(format), local_memory_bits_(local_memory_bits) {}

PpProgram SlicePrograms::setup(bool perspective) const {
    PpProgramBuilder b(perspective ? "wilson slice setup perspective" : "wilson slice setup", local_memory_bits_);
    const SliceState s = allocate_state(b, format_);
    b.enable_all();
    b.assign_const(s.key, 0);
    // The index quadratics are read unsigned: a pixel left of the slice (a negative index) wraps to a
    // huge value, which saturates at the top index and so matches no cell, as a pixel right of it does.
    PpField index[2];
    if (!perspective) {
        for (int e = 0; e < 2; ++e) {
            const PpField q = b.qee(e == 0 ? "u+1" : "v+1", e, kParallelIndexBits, false, kShift);
            index[e] = b.min_const(e == 0 ? "I" : "J", q, kIndexTop);
            b.release(q);
        }
    } else {
        // Only where the slice's plane lies in front of the eye along the pixel's ray.
        const PpField w_raw = b.qee("W", 2, kPerspectiveWBits, true, kShift);
        b.enable_if(w_raw, PpCompare::Greater, 0);
        const PpField w = b.max_const("W_positive", w_raw, 1);
        b.release(w_raw);
        for (int e = 0; e < 2; ++e) {
            const PpField n = b.qee(e == 0 ? "(u+1)W" : "(v+1)W", e, kPerspectiveIndexBits, false, kShift);
            index[e] = b.div(e == 0 ? "I" : "J", n, w, 0, SliceFormat::kIndexBits);
            b.release(n);
        }
        b.release(w);
    }
    const PpField high = b.mul_const("I_shifted", index[0], std::int64_t{1} << SliceFormat::kIndexBits);
    b.release(index[0]);
    const PpField key = b.add("key", high, index[1]);
    b.release(high);
    b.release(index[1]);
    b.assign(s.key, key);
    b.release(key);
    return b.finish();
}

PpProgram SlicePrograms::quad() const {
    const SliceFormat& f = format_;
    PpProgramBuilder b("wilson texel quad", local_memory_bits_);
    const SliceState s = allocate_state(b, f);
    b.enable_all();
    const PpField key = b.qee("quad_key", 0, SliceFormat::kKeyBits, false, 0);
    const PpField differs = b.sub("key_difference", s.key, key);
    b.release(key);
    b.enable_if(differs, PpCompare::Equal, 0);
    b.release(differs);
    for (int c = 0; c < 4; ++c) {
        const PpField v = b.qee("channel", 1 + c, kChannelBits, true, kShift);
        const PpField low = b.max_const("low", v, 0);
        b.release(v);
        assign_clamped(b, s.slice[c], low, f.top());
    }
    return b.finish();
}

PpProgram SlicePrograms::composite() const {
    const SliceFormat& f = format_;
    PpProgramBuilder b("wilson slice composite", local_memory_bits_);
    const SliceState s = allocate_state(b, f);
    b.enable_all();
    const PpField one = b.set_const("one", f.one());
    const PpField clear = b.sub("1-a", one, s.slice[3]);
    b.release(one);
    composite_over(b, s, clear, f, [&](int c) {
        return std::pair{c == 3 ? b.move("a", s.slice[3]) : b.mul("a_c", s.slice[c], s.slice[3], f.accumulator_bits),
                         true};
    });
    for (int c = 0; c < 4; ++c) b.assign_const(s.slice[c], 0);
    return b.finish();
}

PpProgram SlicePrograms::point() const {
    const SliceFormat& f = format_;
    PpProgramBuilder b("wilson point", local_memory_bits_);
    const SliceState s = allocate_state(b, f);
    b.enable_all();
    for (int e = 0; e < 2; ++e) {
        const PpField inside = b.qee(e == 0 ? "x_inside" : "y_inside", e, kQuad, true, 0);
        b.enable_if(inside, PpCompare::GreaterEqual, 0);
        b.release(inside);
    }
    const PpField one = b.set_const("one", f.one());
    const PpField alpha = b.qee("a", 5, f.accumulator_bits, false, 0);
    const PpField clear = b.sub("1-a", one, alpha);
    b.release(one);
    b.release(alpha);
    composite_over(b, s, clear, f, [&](int c) {
        return std::pair{b.qee("a_c", 2 + c, f.accumulator_bits, false, 0), true};
    });
    return b.finish();
}

PpProgram SlicePrograms::block_over() const {
    const SliceFormat& f = format_;
    PpProgramBuilder b("wilson block over", local_memory_bits_);
    const SliceState s = allocate_state(b, f);
    // The controller writes the block's premultiplied pixels into the slice buffer, which is clear
    // between slices (elsewhere it stays zero and changes nothing).
    b.enable_all();
    const PpField one = b.set_const("one", f.one());
    const PpField clear = b.sub("1-a", one, s.slice[3]);
    b.release(one);
    composite_over(b, s, clear, f, [&](int c) { return std::pair{s.slice[c], false}; });
    for (int c = 0; c < 4; ++c) b.assign_const(s.slice[c], 0);
    return b.finish();
}

PpProgram SlicePrograms::readout() const {
    const SliceFormat& f = format_;
    PpProgramBuilder b("wilson readout", local_memory_bits_);
    const SliceState s = allocate_state(b, f);
    b.enable_all();
    // Eight bits a channel for the frame buffer's port.
    for (int c = 0; c < 3; ++c) b.release(b.move("out", s.color[c], f.accumulator_bits - 8));
    return b.finish();
}

std::vector<QeeCoefficients> SlicePrograms::expressions(const QuadDraw& q) {
    return {qee_constant(q.key), q.channels[0], q.channels[1], q.channels[2], q.channels[3]};
}

std::vector<QeeCoefficients> SlicePrograms::expressions(const PointSquare& p) {
    // [0], [1] the square's extent, [2..5] its premultiplied red, green, blue and opacity (the
    // opacity read twice: composited, and for 1 - a).
    const std::int64_t alpha = p.premultiplied[3];
    return {span_test(p.x0, p.x1, true),      span_test(p.y0, p.y1, false),     qee_constant(p.premultiplied[0]),
            qee_constant(p.premultiplied[1]), qee_constant(p.premultiplied[2]), qee_constant(alpha)};
}

SliceRegion::SliceRegion(int c, int r) : columns(c), rows(r) {
    const auto n = static_cast<std::size_t>(c) * static_cast<std::size_t>(r);
    for (auto& v : color) v.assign(n, 0);
    alpha.assign(n, 0);
    for (auto& v : slice) v.assign(n, 0);
    key.assign(n, 0);
}

void setup_slice(SliceRegion& region, const SliceSetup& setup) {
    const auto unsigned_value = [&](int e, int x, int y, int bits) {
        return qee_value(setup.expressions[static_cast<std::size_t>(e)], x, y, kShift, bits, false);
    };
    for (int y = 0; y < region.rows; ++y)
        for (int x = 0; x < region.columns; ++x) {
            const std::size_t p = region.index(x, y);
            region.key[p] = 0;
            std::int64_t index[2];
            if (!setup.perspective) {
                for (int e = 0; e < 2; ++e) index[e] = std::min(unsigned_value(e, x, y, kParallelIndexBits), kIndexTop);
            } else {
                const std::int64_t w = qee_value(setup.expressions[2], x, y, kShift, kPerspectiveWBits, true);
                if (!(w > 0)) continue;
                for (int e = 0; e < 2; ++e)
                    index[e] = std::min(unsigned_value(e, x, y, kPerspectiveIndexBits) / w, kIndexTop);
            }
            region.key[p] = static_cast<std::int32_t>(SliceFormat::key(index[0], index[1]));
        }
}

std::uint32_t draw_quad(SliceRegion& region, const QuadDraw& q, const SliceFormat& f) {
    std::uint32_t changed = 0;
    for (int y = std::max(q.y0, 0); y <= std::min(q.y1, region.rows - 1); ++y)
        for (int x = std::max(q.x0, 0); x <= std::min(q.x1, region.columns - 1); ++x) {
            const std::size_t p = region.index(x, y);
            if (region.key[p] != q.key) continue;
            ++changed;
            for (int c = 0; c < 4; ++c)
                region.slice[c][p] = static_cast<std::int32_t>(std::clamp<std::int64_t>(
                    qee_value(q.channels[static_cast<std::size_t>(c)], x, y, kShift, kChannelBits, true), 0, f.top()));
        }
    return changed;
}

std::uint32_t composite_slice(SliceRegion& region, const SliceFormat& f) {
    std::uint32_t held = 0;
    for (std::size_t p = 0; p < region.alpha.size(); ++p) {
        const std::int64_t a = region.slice[3][p];
        if ((region.slice[0][p] | region.slice[1][p] | region.slice[2][p] | a) == 0) continue;
        ++held;
        const std::int64_t clear = f.one() - a;
        for (int c = 0; c < 3; ++c)
            region.color[c][p] = over(region.color[c][p], (region.slice[c][p] * a) >> f.accumulator_bits, clear, f);
        region.alpha[p] = over(region.alpha[p], a, clear, f);
        for (auto& s : region.slice) s[p] = 0;
    }
    return held;
}

std::uint32_t draw_point_square(SliceRegion& region, const PointSquare& point, const SliceFormat& f) {
    const std::int64_t clear = f.one() - point.premultiplied[3];
    std::uint32_t changed = 0;
    for (int y = std::max(point.y0, 0); y <= std::min(point.y1, region.rows - 1); ++y)
        for (int x = std::max(point.x0, 0); x <= std::min(point.x1, region.columns - 1); ++x) {
            const std::size_t p = region.index(x, y);
            for (int c = 0; c < 3; ++c)
                region.color[c][p] =
                    over(region.color[c][p], point.premultiplied[static_cast<std::size_t>(c)], clear, f);
            region.alpha[p] = over(region.alpha[p], point.premultiplied[3], clear, f);
            ++changed;
        }
    return changed;
}

std::uint32_t composite_point_into(std::vector<std::array<std::int32_t, 4>>& block, int x0, int y0, int x1, int y1,
                                   const PointSquare& point, const SliceFormat& f) {
    const std::int64_t clear = f.one() - point.premultiplied[3];
    const auto w = static_cast<std::size_t>(x1 - x0 + 1);
    std::uint32_t changed = 0;
    for (int y = std::max(point.y0, y0); y <= std::min(point.y1, y1); ++y)
        for (int x = std::max(point.x0, x0); x <= std::min(point.x1, x1); ++x) {
            auto& cell = block[static_cast<std::size_t>(y - y0) * w + static_cast<std::size_t>(x - x0)];
            for (std::size_t c = 0; c < 4; ++c) cell[c] = over(cell[c], point.premultiplied[c], clear, f);
            ++changed;
        }
    return changed;
}

void draw_block_over(SliceRegion& region, int x0, int y0, int x1, int y1,
                     const std::vector<std::array<std::int32_t, 4>>& block, const SliceFormat& f) {
    const auto w = static_cast<std::size_t>(x1 - x0 + 1);
    for (int y = std::max(y0, 0); y <= std::min(y1, region.rows - 1); ++y)
        for (int x = std::max(x0, 0); x <= std::min(x1, region.columns - 1); ++x) {
            const auto& cell = block[static_cast<std::size_t>(y - y0) * w + static_cast<std::size_t>(x - x0)];
            const std::size_t p = region.index(x, y);
            const std::int64_t clear = f.one() - cell[3];
            for (int c = 0; c < 3; ++c)
                region.color[c][p] = over(region.color[c][p], cell[static_cast<std::size_t>(c)], clear, f);
            region.alpha[p] = over(region.alpha[p], cell[3], clear, f);
        }
}

}  // namespace pp5
