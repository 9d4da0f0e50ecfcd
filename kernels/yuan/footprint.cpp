#include "kernels/yuan/footprint.h"

#include "kernels/yuan/splat_geometry.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace pp5 {

GaussianFootprint::GaussianFootprint(double sigma, double radius)
    : sigma_(sigma),
      radius_(radius),
      norm_(1.0 / (2 * std::numbers::pi * sigma * sigma * (1 - std::exp(-radius * radius / (2 * sigma * sigma))))) {}

double GaussianFootprint::operator()(double rho) const {
    // The line integral of a 3-D Gaussian is a 2-D Gaussian of the same sigma; the cut at r is taken on
    // the integrated footprint, so that its integral over the disc is exactly one.
    if (rho >= radius_) return 0.0;
    return norm_ * std::exp(-rho * rho / (2 * sigma_ * sigma_));
}

FootprintTables::FootprintTables(const GaussianFootprint& kernel, int table_bits, int accumulator_bits,
                                 double alpha_step, bool corrected)
    : kernel_(kernel),
      table_bits_(table_bits),
      accumulator_bits_(accumulator_bits),
      alpha_step_(alpha_step),
      corrected_(corrected) {}

int FootprintTables::row_of(double alpha) const {
    if (!corrected_) return 0;
    return static_cast<int>(std::floor(alpha / alpha_step_));
}

const PpTable& FootprintTables::table(int row) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = rows_.find(row);
    if (it == rows_.end()) it = rows_.emplace(row, build(row)).first;
    return it->second;  // std::map keeps references valid as rows are added
}

PpTable FootprintTables::build(int row) const {
    PpTable table;
    table.name = fmt::format("footprint row {}", row);
    const double alpha = (row + 0.5) * alpha_step_;
    const double sin_alpha = corrected_ ? std::sin(alpha) : 0.0;
    const int entries = 1 << table_bits_;
    const double scale = static_cast<double>(std::int64_t{1} << accumulator_bits_);
    const auto top = static_cast<double>((std::int64_t{1} << accumulator_bits_) - 1);
    for (int i = 0; i < entries; ++i) {
        const double i2 = (i + 0.5) / entries;  // the middle of the entry's range of i^2
        const double d2 = corrected_ ? corrected_index_squared(i2, sin_alpha) : i2;
        const double w = kernel_(kernel_.radius() * std::sqrt(d2));
        table.entries.push_back(static_cast<std::int64_t>(std::min(std::round(w * scale), top)));
    }
    return table;
}

}  // namespace pp5
