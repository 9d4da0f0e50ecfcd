#include "kernels/shared/screen_regions/qee_fixed_point.h"

#include <cmath>
#include <stdexcept>

namespace pp5 {

namespace {

std::int64_t wrap(std::int64_t v, int bits, bool is_signed) {
    const std::uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
    const std::uint64_t sign = is_signed ? 1ull << (bits - 1) : 0;
    return static_cast<std::int64_t>(((static_cast<std::uint64_t>(v) & mask) ^ sign) - sign);
}

}  // namespace

QeeCoefficients to_qee(double a, double b, double c, double d, double e, double f, double scale, double bias) {
    const double k = scale * static_cast<double>(std::int64_t{1} << kQeeCoefficientShift);
    const auto q = [k](double v) {
        const double x = std::round(v * k);
        if (!(std::abs(x) < 4.0e18)) throw std::range_error("QEE coefficient out of range");
        return static_cast<std::int64_t>(x);
    };
    return {q(a), q(b), q(c), q(d), q(e), q(f + bias / scale)};
}

QeeCoefficients qee_constant(std::int64_t value) { return {0, 0, 0, 0, 0, value}; }

std::int64_t qee_value(const QeeCoefficients& q, int x, int y, int shift, int bits, bool is_signed) {
    // As the PP array: in uint64, row terms first, then an arithmetic shift and the field's wrap.
    const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v); };
    const std::uint64_t ux = static_cast<std::uint64_t>(x), uy = static_cast<std::uint64_t>(y);
    const std::uint64_t linear = u(q.b) * uy + u(q.d);
    const std::uint64_t constant = u(q.c) * uy * uy + u(q.e) * uy + u(q.f);
    const auto v = static_cast<std::int64_t>(u(q.a) * ux * ux + linear * ux + constant) >> shift;
    return wrap(v, bits, is_signed);
}

}  // namespace pp5
