#pragma once
// JSON a user hands pp5sim (a stats.json to compare, a sweep shard to merge, a change sent to `serve`),
// parsed with a limit on nesting: the parser itself keeps its own stack, but everything that walks the
// result afterwards (comparison, dumping, reading fields) recurses, so a document nested tens of
// thousands deep would overflow the host's stack. Refused up front instead, naming the file and field.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>

namespace pp5 {

inline constexpr int kMostJsonDepth = 128;

// The document in `text`; throws InputError(file, field, why) when it is not JSON or nests deeper
// than `most_depth` arrays and objects.
nlohmann::json parse_json_input(const std::string& text, const std::string& file, const std::string& field,
                                int most_depth = kMostJsonDepth);

// The same for a file, read as it is parsed, so a file that is not JSON (a volume given by mistake) is
// refused at its first bytes rather than read whole. Refused up front when larger than `most_bytes`,
// or when its parsed form (taken as ten times its size, what nlohmann's nodes take for files of short
// numbers and keys) would not fit in this process's memory.
nlohmann::json read_json_file(const std::filesystem::path& path, const std::string& field, std::uintmax_t most_bytes,
                              int most_depth = kMostJsonDepth);

}  // namespace pp5
