#pragma once
// Statistics, registered per component with a name, a unit and a description (gem5's stats groups):
// counters, vectors of named buckets, histograms over fixed bucket bounds, and formulas evaluated
// when the statistics are written. Everything here is integer or derived from integers, so the same
// run gives the same numbers to the last digit.

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pp5 {

class Statistic {
public:
    Statistic(std::string name, std::string unit, std::string description)
        : name_(std::move(name)), unit_(std::move(unit)), description_(std::move(description)) {}
    virtual ~Statistic() = default;
    Statistic(const Statistic&) = delete;
    Statistic& operator=(const Statistic&) = delete;

    const std::string& name() const { return name_; }
    const std::string& unit() const { return unit_; }
    const std::string& description() const { return description_; }

    virtual void reset() = 0;
    virtual nlohmann::json value_json() const = 0;

private:
    std::string name_;
    std::string unit_;
    std::string description_;
};

class Counter final : public Statistic {
public:
    using Statistic::Statistic;
    Counter& operator+=(std::uint64_t n) {
        value_ += n;
        return *this;
    }
    Counter& operator++() {
        ++value_;
        return *this;
    }
    std::uint64_t value() const { return value_; }
    void reset() override { value_ = 0; }
    nlohmann::json value_json() const override;

private:
    std::uint64_t value_ = 0;
};

// A counter per named bucket (e.g. bytes by message type).
class VectorStat final : public Statistic {
public:
    VectorStat(std::string name, std::string unit, std::string description, std::vector<std::string> buckets);
    void add(std::size_t bucket, std::uint64_t n = 1) { values_.at(bucket) += n; }
    std::uint64_t value(std::size_t bucket) const { return values_.at(bucket); }
    std::uint64_t total() const;
    void reset() override;
    nlohmann::json value_json() const override;

private:
    std::vector<std::string> buckets_;
    std::vector<std::uint64_t> values_;
};

// Samples counted into buckets [bounds[i], bounds[i+1]); below the first bound and at or above the last
// go to underflow and overflow.
class Histogram final : public Statistic {
public:
    Histogram(std::string name, std::string unit, std::string description, std::vector<std::int64_t> bounds);
    void sample(std::int64_t x, std::uint64_t count = 1);
    std::uint64_t samples() const { return samples_; }
    std::int64_t sum() const { return sum_; }
    std::uint64_t bucket(std::size_t i) const { return counts_.at(i); }
    std::uint64_t underflow() const { return underflow_; }
    std::uint64_t overflow() const { return overflow_; }
    void reset() override;
    nlohmann::json value_json() const override;

private:
    std::vector<std::int64_t> bounds_;
    std::vector<std::uint64_t> counts_;
    std::uint64_t underflow_ = 0;
    std::uint64_t overflow_ = 0;
    std::uint64_t samples_ = 0;
    std::int64_t sum_ = 0;
};

// A value computed from other statistics when written (a rate, a ratio, a total in seconds).
class Formula final : public Statistic {
public:
    Formula(std::string name, std::string unit, std::string description, std::function<double()> compute)
        : Statistic(std::move(name), std::move(unit), std::move(description)), compute_(std::move(compute)) {}
    double value() const { return compute_(); }
    void reset() override {}
    nlohmann::json value_json() const override;

private:
    std::function<double()> compute_;
};

// The statistics of one component, in registration order (so the JSON is stable).
class StatGroup {
public:
    Counter& counter(std::string name, std::string unit, std::string description);
    VectorStat& vector(std::string name, std::string unit, std::string description, std::vector<std::string> buckets);
    Histogram& histogram(std::string name, std::string unit, std::string description, std::vector<std::int64_t> bounds);
    Formula& formula(std::string name, std::string unit, std::string description, std::function<double()> compute);

    const std::vector<std::unique_ptr<Statistic>>& all() const { return stats_; }
    const Statistic* find(const std::string& name) const;
    void reset();
    // {"name": {"value": ..., "unit": ..., "description": ...}, ...}
    nlohmann::json to_json() const;

private:
    template <class T, class... Args>
    T& add(Args&&... args);

    std::vector<std::unique_ptr<Statistic>> stats_;
};

}  // namespace pp5
