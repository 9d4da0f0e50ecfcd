#pragma once
// Internal to scene/scenario: how scenario files spell vectors and small counts.

#include "sim/core/toml_table.h"

#include <glm/vec3.hpp>

#include <optional>
#include <string>

namespace pp5::scenario_values {

// A scenario's vectors, as floats.
inline std::optional<glm::vec3> vec3(TomlTable& table, const std::string& key, double min, double max) {
    const auto v = table.triple(key, min, max);
    if (!v) return std::nullopt;
    return glm::vec3(static_cast<float>((*v)[0]), static_cast<float>((*v)[1]), static_cast<float>((*v)[2]));
}

// A scenario's counts and sizes, all of which fit an int.
inline std::optional<int> small_integer(TomlTable& table, const std::string& key, int min, int max) {
    const auto v = table.integer(key, min, max);
    if (!v) return std::nullopt;
    return static_cast<int>(*v);
}

// The bound of numbers with no natural one (coordinates, light directions).
inline constexpr double kHuge = 1e9;

}  // namespace pp5::scenario_values
