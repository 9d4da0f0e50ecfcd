#pragma once
// Files that may be named by path or by the name of a shipped preset (machines, scenarios).

#include <filesystem>
#include <string>
#include <vector>

namespace pp5 {

struct NamedFileSearch {
    const char* environment_variable;  // a directory the user can add, searched first
    const char* builtin_directory;     // the source tree's presets; may be null
    const char* field;                 // how the user gave the name, for the error
    const char* hint;                  // where the shipped names are, for the error
};

// `name_or_path` if it is an existing file, else NAME.toml in the search directories.
// Throws pp5::InputError naming the argument when neither exists.
std::filesystem::path resolve_named_file(const std::string& name_or_path, const NamedFileSearch& search);
// Every NAME.toml the search directories hold, by name (the user's directory first shadows a
// shipped file of the same name).
std::vector<std::filesystem::path> list_named_files(const NamedFileSearch& search);

// Why `name` cannot name an output folder (out/<name>, out/sweeps/<name>), or "" when it can: one
// plain component of 1 to 100 characters, not . or .., so that nothing written under it lands
// outside the folder it was meant for.
std::string output_name_problem(const std::string& name);

}  // namespace pp5
