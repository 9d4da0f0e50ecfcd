#pragma once
// Simulated time. Everything in the timing model is an integer number of picoseconds, so that adding
// the costs of a billion events never drifts (gem5 and GPGPU-Sim keep clocks as doubles; we do not).

#include <cstdint>

namespace pp5 {

using Tick = std::int64_t;  // picoseconds

inline constexpr Tick kTicksPerSecond = 1'000'000'000'000;
inline constexpr Tick kMaxTick = INT64_MAX;

constexpr double ticks_to_seconds(Tick t) { return static_cast<double>(t) / static_cast<double>(kTicksPerSecond); }

}  // namespace pp5
