#pragma once
// The shape of a sweep.json or shard file, checked whole before anything reads it. These files travel
// between machines (shards are copied back from batch nodes and merged), so a reader trusts nothing in
// them: every field it uses must be there with the right type, counts must be whole numbers, and the
// header's grid must add up to its total.

#include <nlohmann/json.hpp>

#include <string>

namespace pp5 {

// Throws InputError naming `file` and the first field that is missing, mistyped or inconsistent.
// A "shard" object, when present, must hold index < count.
void check_sweep_json_shape(const nlohmann::json& json, const std::string& file);

}  // namespace pp5
