#include "sim/core/toml_file.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace pp5 {

namespace {

// No input of ours comes near these; beyond them a file is refused before it is parsed.
constexpr std::uintmax_t kMostBytes = std::uintmax_t{64} << 20;
constexpr int kMostKeyParts = 64;

// A key of thousands of dotted parts ("a.a.a...") makes toml++ build, and later tear down, a table
// that deep by recursion, past the stack's end. Find the longest key (in a [table] header, before an
// "=", or in an inline table) without parsing: dots outside strings and comments, between a key's
// start (a line, "{", "," or "[") and its end ("=" or "]").
void check_key_depth(const std::string& text, const std::string& file) {
    int parts = 1, line = 1;
    bool in_comment = false;
    char quote = 0;  // inside a string: its quote character
    bool multiline = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') ++line;
        if (in_comment) {
            in_comment = c != '\n';
            if (!in_comment) parts = 1;
            continue;
        }
        if (quote != 0) {
            if (c == '\\' && quote == '"') {
                ++i;
                continue;
            }
            if (c == quote && (!multiline || text.compare(i, 3, std::string(3, quote)) == 0)) {
                i += multiline ? 2 : 0;
                quote = 0;
            }
            continue;
        }
        switch (c) {
            case '"':
            case '\'':
                quote = c;
                multiline = text.compare(i, 3, std::string(3, c)) == 0;
                i += multiline ? 2 : 0;
                break;
            case '#': in_comment = true; break;
            case '.': ++parts; break;
            case '=':
            case ']':
                if (parts > kMostKeyParts)
                    throw InputError(
                        file, fmt::format("line {}", line),
                        fmt::format(
                            "a key of {} dotted parts; none of pp5sim's is more than a few, and at most {} are read",
                            parts, kMostKeyParts));
                parts = 1;
                break;
            case '\n':
            case '{':
            case ',':
            case '[': parts = 1; break;
            default: break;
        }
    }
}

}  // namespace

toml::table read_toml_file(const std::string& file) {
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(file, error);
    if (!error && bytes > kMostBytes)
        throw InputError(file, "",
                         fmt::format("is {} MB; a pp5sim input file is at most {} MB", bytes >> 20, kMostBytes >> 20));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file, "", "cannot be opened");
    std::stringstream buffer;
    buffer << in.rdbuf();
    return read_toml_text(buffer.str(), file);
}

toml::table read_toml_text(const std::string& text, const std::string& file) {
    if (text.size() > kMostBytes)
        throw InputError(file, "",
                         fmt::format("is {} MB; a pp5sim input is at most {} MB", text.size() >> 20, kMostBytes >> 20));
    check_key_depth(text, file);
    try {
        return toml::parse(text, file);
    } catch (const toml::parse_error& e) {
        const auto& where = e.source().begin;
        throw InputError(file, fmt::format("line {}, column {}", where.line, where.column),
                         std::string(e.description()));
    }
}

}  // namespace pp5
