#pragma once
// Values to try for a declared parameter in tests that change one parameter at a time.

#include "sim/core/param.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

namespace pp5::test {

// Values of `spec` other than its default that the parameter accepts, as `--set` would take them:
// the plausible range's ends first, then twice and half the default, the allowed range's ends and 0,
// 1 and 2 (where a parameter's meaning changes: a limit of -1 that means none);
// nothing when there is none.
inline std::vector<std::string> other_values(const ParamSpec& spec) {
    std::vector<std::string> out;
    if (spec.type == ParamType::Boolean) return {std::get<bool>(spec.default_value) ? "false" : "true"};
    if (spec.type == ParamType::Text) {
        if (spec.choices.empty()) return {"other words"};
        for (const std::string& choice : spec.choices)
            if (choice != std::get<std::string>(spec.default_value)) out.push_back(choice);
        return out;
    }
    const bool integer = spec.type == ParamType::Integer;
    const double def = integer ? static_cast<double>(std::get<std::int64_t>(spec.default_value))
                               : std::get<double>(spec.default_value);
    std::vector<double> candidates;
    if (spec.plausible) candidates = {spec.plausible->high, spec.plausible->low};
    candidates.insert(candidates.end(),
                      {def * 2 + 1, def / 2, spec.max.value_or(def), spec.min.value_or(def), 0.0, 1.0, 2.0});
    for (double v : candidates) {
        const ParamValue value = integer ? ParamValue(static_cast<std::int64_t>(std::llround(v))) : ParamValue(v);
        if (value != spec.default_value && spec.check(value).empty()) {
            const std::string text = integer ? std::to_string(std::get<std::int64_t>(value)) : fmt::format("{}", v);
            if (std::find(out.begin(), out.end(), text) == out.end()) out.push_back(text);
        }
    }
    return out;
}

}  // namespace pp5::test
