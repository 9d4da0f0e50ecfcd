#pragma once
// A clock domain: a named integer period. Components count their work in their own cycles and the
// domain turns cycles into simulated time.

#include "sim/core/time.h"

#include <cstdint>
#include <string>

namespace pp5 {

class ClockDomain {
public:
    ClockDomain(std::string name, Tick period_ps);
    // The period nearest to 1/frequency; the effective frequency may differ from the requested one by
    // the rounding to whole picoseconds (under 0.01% up to 100 MHz) and is what config.json reports.
    static ClockDomain from_megahertz(std::string name, double megahertz);

    const std::string& name() const { return name_; }
    Tick period() const { return period_ps_; }
    double frequency_hz() const { return static_cast<double>(kTicksPerSecond) / static_cast<double>(period_ps_); }

    Tick cycles_to_ticks(std::uint64_t cycles) const { return static_cast<Tick>(cycles) * period_ps_; }
    // Whole cycles elapsed by `t`, rounding down.
    std::uint64_t ticks_to_cycles(Tick t) const { return static_cast<std::uint64_t>(t / period_ps_); }
    // The first clock edge at or after `t` (edges at multiples of the period).
    Tick next_edge(Tick t) const { return ((t + period_ps_ - 1) / period_ps_) * period_ps_; }

private:
    std::string name_;
    Tick period_ps_;
};

}  // namespace pp5
