#include "sim/core/toml_file.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

namespace pp5 {

toml::table read_toml_file(const std::string& file) {
    try {
        return toml::parse_file(file);
    } catch (const toml::parse_error& e) {
        const auto& where = e.source().begin;
        throw InputError(file, fmt::format("line {}, column {}", where.line, where.column), std::string(e.description()));
    }
}

}  // namespace pp5
