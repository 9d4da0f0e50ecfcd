#pragma once
// JSON a user hands pp5sim (a stats.json to compare, a sweep shard to merge, a change sent to `serve`),
// parsed with a limit on nesting: the parser itself keeps its own stack, but everything that walks the
// result afterwards (comparison, dumping, reading fields) recurses, so a document nested tens of
// thousands deep would overflow the host's stack. Refused up front instead, naming the file and field.

#include <nlohmann/json.hpp>

#include <string>

namespace pp5 {

inline constexpr int kMostJsonDepth = 128;

// The document in `text`; throws InputError(file, field, why) when it is not JSON or nests deeper
// than `most_depth` arrays and objects.
nlohmann::json parse_json_input(const std::string& text, const std::string& file, const std::string& field,
                                int most_depth = kMostJsonDepth);

}  // namespace pp5
