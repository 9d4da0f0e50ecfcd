#pragma once
// Integer helpers shared by the PP program builder (value ranges) and the PP array (execution).

#include <cmath>
#include <cstdint>

namespace pp5 {

// floor(sqrt(x)) exactly, 0 for x <= 0: a double estimate corrected by integer checks.
inline std::int64_t pp_isqrt(std::int64_t x) {
    if (x <= 0) return 0;
    auto r = static_cast<std::int64_t>(std::sqrt(static_cast<double>(x)));
    while (r * r > x) --r;
    while ((r + 1) * (r + 1) <= x) ++r;
    return r;
}

}  // namespace pp5
