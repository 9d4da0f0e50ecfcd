#include "sim/core/clock_domain.h"

#include <cmath>
#include <stdexcept>

namespace pp5 {

ClockDomain::ClockDomain(std::string name, Tick period_ps) : name_(std::move(name)), period_ps_(period_ps) {
    if (period_ps_ <= 0) throw std::invalid_argument("clock domain " + name_ + ": period must be positive");
}

ClockDomain ClockDomain::from_megahertz(std::string name, double megahertz) {
    if (!(megahertz > 0.0) || !std::isfinite(megahertz))
        throw std::invalid_argument("clock domain " + name + ": frequency must be positive");
    const double period = 1e6 / megahertz;  // picoseconds per cycle
    return ClockDomain(std::move(name), std::max<Tick>(1, std::llround(period)));
}

}  // namespace pp5
