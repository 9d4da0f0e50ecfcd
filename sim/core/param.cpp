#include "sim/core/param.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <stdexcept>

namespace pp5 {

std::string to_string(ParamType type) {
    switch (type) {
        case ParamType::Integer: return "integer";
        case ParamType::Real: return "real";
        case ParamType::Boolean: return "boolean";
        case ParamType::Text: return "text";
    }
    return "?";
}

std::string to_string(Provenance provenance) {
    switch (provenance) {
        case Provenance::Paper: return "paper";
        case Provenance::Hardware: return "hardware";
        case Provenance::Default: return "default";
    }
    return "?";
}

std::string format_param_value(const ParamValue& value) {
    return std::visit(
        [](const auto& v) -> std::string {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
            else if constexpr (std::is_same_v<T, std::string>) return "\"" + v + "\"";
            else return fmt::format("{}", v);
        },
        value);
}

std::string ParamSpec::check(const ParamValue& value) const {
    const auto in_range = [&](double x) -> std::string {
        if (!std::isfinite(x)) return "must be a finite number";
        if ((min && x < *min) || (max && x > *max))
            return fmt::format("{} is outside the allowed range [{}, {}]{}", x, min.value_or(-INFINITY),
                               max.value_or(INFINITY), unit.empty() ? "" : " " + unit);
        return {};
    };
    switch (type) {
        case ParamType::Integer:
            if (!std::holds_alternative<std::int64_t>(value)) return "must be an integer";
            return in_range(static_cast<double>(std::get<std::int64_t>(value)));
        case ParamType::Real:
            if (std::holds_alternative<std::int64_t>(value))
                return in_range(static_cast<double>(std::get<std::int64_t>(value)));
            if (!std::holds_alternative<double>(value)) return "must be a number";
            return in_range(std::get<double>(value));
        case ParamType::Boolean:
            if (!std::holds_alternative<bool>(value)) return "must be true or false";
            return {};
        case ParamType::Text: {
            if (!std::holds_alternative<std::string>(value)) return "must be a string";
            if (choices.empty()) return {};
            for (const auto& c : choices)
                if (c == std::get<std::string>(value)) return {};
            return fmt::format("\"{}\" is not one of: {}", std::get<std::string>(value), fmt::join(choices, ", "));
        }
    }
    return "unknown parameter type";
}

ParamGroup::ParamGroup(std::string prefix, std::string description)
    : prefix_(std::move(prefix)), description_(std::move(description)) {}

ParamGroup& ParamGroup::add(ParamSpec spec) {
    for (const auto& existing : specs_)
        if (existing.name == spec.name)
            throw std::logic_error("parameter declared twice: " + prefix_ + "." + spec.name);
    if (const std::string why = spec.check(spec.default_value); !why.empty())
        throw std::logic_error("default of " + prefix_ + "." + spec.name + " " + why);
    spec.timing_only = spec.timing_only || all_timing_only_;
    specs_.push_back(std::move(spec));
    return *this;
}

ParamGroup& ParamGroup::timing_only() {
    if (specs_.empty()) throw std::logic_error("timing_only before any parameter of " + prefix_);
    specs_.back().timing_only = true;
    return *this;
}

ParamGroup& ParamGroup::all_timing_only() {
    all_timing_only_ = true;
    for (ParamSpec& spec : specs_) spec.timing_only = true;
    return *this;
}

ParamGroup& ParamGroup::plausible(double low, double high, std::string why) {
    if (specs_.empty()) throw std::logic_error("plausible range before any parameter of " + prefix_);
    ParamSpec& spec = specs_.back();
    const std::string key = prefix_ + "." + spec.name;
    if (spec.type != ParamType::Integer && spec.type != ParamType::Real)
        throw std::logic_error("plausible range of " + key + ", which is not a number");
    const double def = spec.type == ParamType::Integer ? static_cast<double>(std::get<std::int64_t>(spec.default_value))
                                                       : std::get<double>(spec.default_value);
    if (!(low <= def && def <= high))
        throw std::logic_error(
            fmt::format("plausible range of {} [{}, {}] leaves out its default {}", key, low, high, def));
    const auto as_value = [&](double x) {
        return spec.type == ParamType::Integer ? ParamValue(static_cast<std::int64_t>(std::llround(x))) : ParamValue(x);
    };
    if (!spec.check(as_value(low)).empty() || !spec.check(as_value(high)).empty())
        throw std::logic_error(fmt::format("plausible range of {} [{}, {}] leaves the allowed range", key, low, high));
    if (why.empty()) throw std::logic_error("plausible range of " + key + " without a reason");
    spec.plausible = PlausibleRange{low, high, std::move(why)};
    return *this;
}

ParamGroup& ParamGroup::plausible_factor(double low_factor, double high_factor, std::string why) {
    if (specs_.empty()) throw std::logic_error("plausible range before any parameter of " + prefix_);
    const ParamSpec& spec = specs_.back();
    const double def = spec.type == ParamType::Integer ? static_cast<double>(std::get<std::int64_t>(spec.default_value))
                                                       : std::get<double>(spec.default_value);
    double low = def * low_factor, high = def * high_factor;
    if (spec.type == ParamType::Integer) low = std::floor(low), high = std::ceil(high);
    return plausible(low, high, std::move(why));
}

ParamGroup& ParamGroup::hand_counted() {
    plausible_factor(0.5, 2,
                     "counted by hand from the arithmetic: compiled code could need half (fused or paired "
                     "instructions) or twice as many (the loads, conversions and loop control a count leaves out)");
    specs_.back().plausible->per_operation = true;
    return *this;
}

ParamGroup& ParamGroup::hand_counted_flops(std::string name, double def, std::string doc, std::string count) {
    return real(std::move(name), def, "flops", 0, 1e6, std::move(doc), Provenance::Default, std::move(count))
        .hand_counted();
}

ParamGroup& ParamGroup::hand_counted_cycles(std::string name, double def, std::string doc, std::string count) {
    return real(std::move(name), def, "cycles", 0, 1e7, std::move(doc), Provenance::Default, std::move(count))
        .hand_counted();
}

ParamGroup& ParamGroup::integer(std::string name, std::int64_t def, std::string unit, double min, double max,
                                std::string doc, Provenance provenance, std::string source) {
    return add(ParamSpec{std::move(name),
                         ParamType::Integer,
                         std::move(unit),
                         def,
                         min,
                         max,
                         {},
                         std::move(doc),
                         provenance,
                         std::move(source),
                         std::nullopt});
}

ParamGroup& ParamGroup::real(std::string name, double def, std::string unit, double min, double max, std::string doc,
                             Provenance provenance, std::string source) {
    return add(ParamSpec{std::move(name),
                         ParamType::Real,
                         std::move(unit),
                         def,
                         min,
                         max,
                         {},
                         std::move(doc),
                         provenance,
                         std::move(source),
                         std::nullopt});
}

ParamGroup& ParamGroup::boolean(std::string name, bool def, std::string doc, Provenance provenance,
                                std::string source) {
    return add(ParamSpec{std::move(name),
                         ParamType::Boolean,
                         "",
                         def,
                         std::nullopt,
                         std::nullopt,
                         {},
                         std::move(doc),
                         provenance,
                         std::move(source),
                         std::nullopt});
}

ParamGroup& ParamGroup::text(std::string name, std::string def, std::vector<std::string> choices, std::string doc,
                             Provenance provenance, std::string source) {
    return add(ParamSpec{std::move(name), ParamType::Text, "", std::move(def), std::nullopt, std::nullopt,
                         std::move(choices), std::move(doc), provenance, std::move(source), std::nullopt});
}

}  // namespace pp5
