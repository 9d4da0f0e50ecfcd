#pragma once
// What a renderer does to the screen region it owns, in fixed point: draw a splat (its footprint
// weight from the QEE and a table, composited "over" or summed into the band sheet), filter a point
// into the sheet, add a block of sheet pixels the GPs sent, composite the sheet at a band's end, and
// read the region out. Each exists twice:
//   - as a PP program from PpProgramBuilder, whose instructions give its cost on the renderer (and
//     whose fit in local memory is checked), run on a PpArray in the tests;
//   - as its functional twin: plain integer code applying exactly the same arithmetic to the pixels in
//     the primitive's bounding box only (running the PP array over all 16K PPs per primitive would be
//     far too slow for a million splats). A test runs both on random primitives and compares every pixel.
//
// The region's state lives in each PP's local memory from primitive to primitive: colour and opacity
// accumulators C, A (accumulator_bits of fraction) and the band sheet S (two more fraction bits, values
// below 4). Every program allocates them first and in the same order, so they sit in the same fields.

#include "kernels/shared/screen_regions/qee_fixed_point.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_program.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pp5 {

struct RegionFormat {
    int accumulator_bits = 12;                                     // fraction bits of C and A (1.0 = 2^bits)
    int table_bits = 6;                                            // footprint table entries: 2^bits over i^2
    int sheet_bits() const { return accumulator_bits + 2; }        // fraction bits of S
    int sheet_field_bits() const { return accumulator_bits + 4; }  // S holds values below 4
    std::int64_t one() const { return std::int64_t{1} << accumulator_bits; }
    std::int64_t sheet_one() const { return std::int64_t{1} << sheet_bits(); }

    static constexpr int kIndexBits = 16;  // the squared index i^2 (1.0 = 2^16, the silhouette)
    static constexpr int kCoefficientShift = kQeeCoefficientShift;
    static constexpr int kQuadraticBits = kQeeResultBits;
};

enum class SplatIndexMode { Affine, Exact };  // Yuan's affine index (its correction in the table), or exact d^2 = N / M
enum class SplatBlend { Over, Sheet };

// The QEE expressions of one splat in one region, and what the twin needs besides.
struct SplatDraw {
    // Affine: [0] i^2 in kIndexBits; Exact: [0] N, [1] M with d^2 = N / M in kIndexBits.
    // Then the constants: opacity, red, green, blue, in accumulator units.
    std::vector<QeeCoefficients> expressions;
    int table = 0;                         // the footprint row it is drawn with
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // region-local box (inclusive) outside which no pixel is inside
};

// A point's four paraboloids (red, green, blue, opacity weights, in sheet units) in one region.
struct PointDraw {
    std::array<QeeCoefficients, 4> expressions;
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

class RegionPrograms {
public:
    RegionPrograms(const RegionFormat& format, SplatIndexMode mode, SplatBlend blend, int local_memory_bits);
    // The splat program drawing with footprint table `table` (its entries in accumulator units).
    PpProgram splat(const PpTable& table) const;
    PpProgram point() const;
    PpProgram sheet_add() const;  // four staged words per pixel added into the sheet
    PpProgram band_composite() const;
    PpProgram readout() const;
    const RegionFormat& format() const { return format_; }
    SplatIndexMode mode() const { return mode_; }
    SplatBlend blend() const { return blend_; }

private:
    RegionFormat format_;
    SplatIndexMode mode_;
    SplatBlend blend_;
    int local_memory_bits_;
};

// The twins' state: one region's pixels (columns x rows, row-major), the same values the PPs hold.
struct RegionPixels {
    int columns = 0, rows = 0;
    std::vector<std::int32_t> color[3], alpha, sheet[4];  // sheet: r, g, b, opacity
    RegionPixels(int c, int r);
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(x);
    }
};

// The twins. Each returns the pixels it changed (enabled, for the counts a lone processor is charged).
std::uint32_t draw_splat(RegionPixels& region, const SplatDraw& splat, const PpTable& table, const RegionFormat& format,
                         SplatIndexMode mode, SplatBlend blend);
std::uint32_t draw_point(RegionPixels& region, const PointDraw& point, const RegionFormat& format);
// What the GP does on the gp_sheets path: adds the point's sheet values into `block`, the pixels
// [x0, x1] x [y0, y1] row-major, each clamped as the renderer's sheet is; returns the pixels it reached.
std::uint32_t filter_point(const PointDraw& point, const RegionFormat& format, int x0, int y0, int x1, int y1,
                           std::vector<std::array<std::int32_t, 4>>& block);
void add_sheet_block(RegionPixels& region, int x0, int y0, int x1, int y1,
                     const std::vector<std::array<std::int32_t, 4>>& block, const RegionFormat& format);
// Composites the sheet into C, A and clears it; returns the pixels whose sheet held something.
std::uint32_t composite_band(RegionPixels& region, const RegionFormat& format);

}  // namespace pp5
