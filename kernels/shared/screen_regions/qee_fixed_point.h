#pragma once
// The renderers' quadratic expression evaluator in fixed point, as the GPs must feed it: a float
// quadratic of region-local pixel coordinates turned into integer coefficients, and the value the PP
// array computes from them at one pixel (so a kernel's host twin of a region program gets exactly the
// PPs' numbers).

#include "sim/pixel_processors/pp_array.h"

#include <cstdint>

namespace pp5 {

inline constexpr int kQeeCoefficientShift = 24;  // coefficients carry 24 fraction bits
inline constexpr int kQeeResultBits = 40;        // width of a result field that holds any such quadratic

// A float quadratic (of region-local pixel coordinates) as the QEE's fixed-point coefficients; `bias`
// is added to the result (in result units) after scaling, to keep a quantity that is never negative
// from rounding below zero.
QeeCoefficients to_qee(double a, double b, double c, double d, double e, double f, double scale, double bias = 0);
QeeCoefficients qee_constant(std::int64_t value);  // evaluated with shift 0

// The QEE's value at region-local (x, y), exactly as the PP array computes it, wrapped to `bits`.
std::int64_t qee_value(const QeeCoefficients& q, int x, int y, int shift, int bits, bool is_signed);

}  // namespace pp5
