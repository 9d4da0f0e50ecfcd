#pragma once
// "Did you mean ...?": the nearest of a set of names to one a user typed, for every error about a
// name that does not exist (a command, an option, a parameter key, a scenario, a dataset, a phantom).

#include <string>
#include <string_view>
#include <vector>

namespace pp5 {

// Edits (insert, delete, replace, swap two neighbours) that turn a into b: the slips typing makes.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The nearest of `names` to `given` if it is near enough to be a slip of the keyboard (fewer edits
// than a third of the word, and at least two allowed), else empty.
std::string closest_name(std::string_view given, const std::vector<std::string>& names);

// "; did you mean NAME?" for the nearest name, or nothing.
std::string did_you_mean(std::string_view given, const std::vector<std::string>& names);

}  // namespace pp5
