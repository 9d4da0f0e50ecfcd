#pragma once
// Reads a TOML file for any of pp5sim's inputs (machine files, scenarios, target files); a syntax error
// is an InputError naming the file, the line and column, and what is wrong.

#include <toml++/toml.h>

#include <string>

namespace pp5 {

toml::table read_toml_file(const std::string& file);
// The same for text already in memory (a scenario built in Python, say); `file` names it in errors.
toml::table read_toml_text(const std::string& text, const std::string& file);

}  // namespace pp5
