#pragma once
// What a renderer does to the screen region it owns for Wilson's slices, in fixed point:
//   - slice setup: each PP finds which texel cell of the slice its pixel sees (a key K = 4096 I + J,
//     with I, J one more than the cell's indices, 0 off the slice), from one quadratic per index under
//     a parallel camera, or from a quotient of two under perspective;
//   - texel quad: the PPs whose key is the quad's write its colour and opacity, each one quadratic of
//     the pixel position (bilinear interpolation in the cell), into the slice buffer;
//   - slice composite: the slice buffer goes under nothing and over everything behind it (back to
//     front: C = a c + (1 - a) C), and is cleared;
//   - point: the PPs inside the point's square composite its colour over what is there;
//   - block over: a block of pixels the GPs composited (premultiplied), written into the slice buffer
//     between slices, goes over the region;
//   - readout.
// Each exists twice, as a PpProgramBuilder program (its instructions give its cost, its fit in local
// memory is checked) and as its functional twin, the same integer arithmetic on the pixels a
// primitive can reach; a test runs both and compares every PP.
//
// The region state every program allocates first, in the same order: C (red, green, blue), A, the slice
// buffer S (red, green, blue, opacity; colour not premultiplied) and the cell key K.

#include "kernels/shared/screen_regions/qee_fixed_point.h"
#include "sim/pixel_processors/pp_program.h"

#include <array>
#include <cstdint>
#include <vector>

namespace pp5 {

struct SliceFormat {
    int accumulator_bits = 12;
    std::int64_t one() const { return std::int64_t{1} << accumulator_bits; }
    std::int64_t top() const { return one() - 1; }  // what a field saturates at

    static constexpr int kIndexBits = 12;  // I and J: cells 0 to 4093 (one more stored, 0 off the slice)
    static constexpr int kKeyBits = 2 * kIndexBits;
    static constexpr std::int64_t key(std::int64_t i, std::int64_t j) { return (i << kIndexBits) + j; }
    // Under perspective the index quadratics carry this many more fraction bits before the divide.
    static constexpr int kPerspectiveScaleBits = 6;
};

// The setup's expressions: parallel, [0] u + 1 and [1] v + 1 (cell units, shifted by the QEE's
// coefficient shift); perspective, [0] (u + 1) W, [1] (v + 1) W and [2] W, each scaled by
// 2^kPerspectiveScaleBits, where u = U / W.
struct SliceSetup {
    bool perspective = false;
    std::vector<QeeCoefficients> expressions;
};

// One texel cell of a slice in one region: its key, and red, green, blue, opacity as quadratics in
// accumulator units; the box of region pixels it can reach.
struct QuadDraw {
    std::int64_t key = 0;
    std::array<QeeCoefficients, 4> channels;
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

// A square point in one region: the pixels [x0, x1] x [y0, y1], its premultiplied colour and opacity
// in accumulator units.
struct PointSquare {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    std::array<std::int64_t, 4> premultiplied{};  // a r, a g, a b, a
};

class SlicePrograms {
public:
    SlicePrograms(const SliceFormat& format, int local_memory_bits);
    PpProgram setup(bool perspective) const;
    PpProgram quad() const;
    PpProgram composite() const;
    PpProgram point() const;
    PpProgram block_over() const;  // four words a pixel, written into the slice buffer by the controller
    PpProgram readout() const;
    const SliceFormat& format() const { return format_; }
    // The QEE expressions of a quad and of a point, as the slot context supplies them.
    static std::vector<QeeCoefficients> expressions(const QuadDraw& quad);
    static std::vector<QeeCoefficients> expressions(const PointSquare& point);

private:
    SliceFormat format_;
    int local_memory_bits_;
};

// The twins' state: one region's fields, row-major.
struct SliceRegion {
    int columns = 0, rows = 0;
    std::vector<std::int32_t> color[3], alpha, slice[4], key;
    SliceRegion(int c, int r);
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(x);
    }
};

void setup_slice(SliceRegion& region, const SliceSetup& setup);
// Each returns the pixels it changed.
std::uint32_t draw_quad(SliceRegion& region, const QuadDraw& quad, const SliceFormat& format);
std::uint32_t composite_slice(SliceRegion& region, const SliceFormat& format);
std::uint32_t draw_point_square(SliceRegion& region, const PointSquare& point, const SliceFormat& format);
// What a GP does on the gp_sheets path: composites the point over `block` (premultiplied, the pixels
// [x0, x1] x [y0, y1] row-major) exactly as the renderer would over its region.
std::uint32_t composite_point_into(std::vector<std::array<std::int32_t, 4>>& block, int x0, int y0, int x1, int y1,
                                   const PointSquare& point, const SliceFormat& format);
void draw_block_over(SliceRegion& region, int x0, int y0, int x1, int y1,
                     const std::vector<std::array<std::int32_t, 4>>& block, const SliceFormat& format);

}  // namespace pp5
