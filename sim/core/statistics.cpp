#include "sim/core/statistics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace pp5 {

nlohmann::json Counter::value_json() const { return value_; }

VectorStat::VectorStat(std::string name, std::string unit, std::string description, std::vector<std::string> buckets)
    : Statistic(std::move(name), std::move(unit), std::move(description)),
      buckets_(std::move(buckets)),
      values_(buckets_.size(), 0) {}

std::uint64_t VectorStat::total() const { return std::accumulate(values_.begin(), values_.end(), std::uint64_t{0}); }
void VectorStat::reset() { std::fill(values_.begin(), values_.end(), 0); }

nlohmann::json VectorStat::value_json() const {
    nlohmann::json out = nlohmann::json::object();
    for (std::size_t i = 0; i < buckets_.size(); ++i) out[buckets_[i]] = values_[i];
    return out;
}

Histogram::Histogram(std::string name, std::string unit, std::string description, std::vector<std::int64_t> bounds)
    : Statistic(std::move(name), std::move(unit), std::move(description)), bounds_(std::move(bounds)) {
    if (bounds_.size() < 2 || !std::is_sorted(bounds_.begin(), bounds_.end()))
        throw std::logic_error("histogram " + this->name() + " needs at least two increasing bounds");
    counts_.assign(bounds_.size() - 1, 0);
}

void Histogram::sample(std::int64_t x, std::uint64_t count) {
    samples_ += count;
    sum_ += x * static_cast<std::int64_t>(count);
    if (x < bounds_.front()) {
        underflow_ += count;
    } else if (x >= bounds_.back()) {
        overflow_ += count;
    } else {
        const auto it = std::upper_bound(bounds_.begin(), bounds_.end(), x);
        counts_[static_cast<std::size_t>(it - bounds_.begin() - 1)] += count;
    }
}

void Histogram::reset() {
    std::fill(counts_.begin(), counts_.end(), 0);
    underflow_ = overflow_ = samples_ = 0;
    sum_ = 0;
}

nlohmann::json Histogram::value_json() const {
    return {{"bounds", bounds_},     {"counts", counts_},   {"underflow", underflow_},
            {"overflow", overflow_}, {"samples", samples_}, {"sum", sum_}};
}

nlohmann::json Formula::value_json() const {
    const double v = compute_();
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

template <class T, class... Args>
T& StatGroup::add(Args&&... args) {
    auto stat = std::make_unique<T>(std::forward<Args>(args)...);
    if (find(stat->name())) throw std::logic_error("statistic registered twice: " + stat->name());
    T& ref = *stat;
    stats_.push_back(std::move(stat));
    return ref;
}

Counter& StatGroup::counter(std::string name, std::string unit, std::string description) {
    return add<Counter>(std::move(name), std::move(unit), std::move(description));
}
VectorStat& StatGroup::vector(std::string name, std::string unit, std::string description,
                              std::vector<std::string> buckets) {
    return add<VectorStat>(std::move(name), std::move(unit), std::move(description), std::move(buckets));
}
Histogram& StatGroup::histogram(std::string name, std::string unit, std::string description,
                                std::vector<std::int64_t> bounds) {
    return add<Histogram>(std::move(name), std::move(unit), std::move(description), std::move(bounds));
}
Formula& StatGroup::formula(std::string name, std::string unit, std::string description,
                            std::function<double()> compute) {
    return add<Formula>(std::move(name), std::move(unit), std::move(description), std::move(compute));
}

const Statistic* StatGroup::find(const std::string& name) const {
    for (const auto& s : stats_)
        if (s->name() == name) return s.get();
    return nullptr;
}

void StatGroup::reset() {
    for (auto& s : stats_) s->reset();
}

nlohmann::json StatGroup::to_json() const {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& s : stats_)
        out[s->name()] = {{"value", s->value_json()}, {"unit", s->unit()}, {"description", s->description()}};
    return out;
}

}  // namespace pp5
