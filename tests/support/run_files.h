#pragma once
// What tests that run the pp5sim binary share: reading its output files, and its statistics without
// the host timings that differ from run to run.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pp5::test {

inline std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

inline nlohmann::json without_host_fields(nlohmann::json j) {
    if (j.is_object()) {
        j.erase("host_seconds");
        for (auto& [k, v] : j.items()) v = without_host_fields(v);
    } else if (j.is_array()) {
        for (auto& v : j) v = without_host_fields(v);
    }
    return j;
}

}  // namespace pp5::test
