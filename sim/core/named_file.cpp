#include "sim/core/named_file.h"

#include "sim/core/input_error.h"

#include <cstdlib>
#include <vector>

namespace pp5 {

std::filesystem::path resolve_named_file(const std::string& name_or_path, const NamedFileSearch& search) {
    namespace fs = std::filesystem;
    if (fs::is_regular_file(name_or_path)) return name_or_path;
    const std::string file_name = name_or_path + ".toml";
    std::vector<fs::path> directories;
    if (const char* env = std::getenv(search.environment_variable)) directories.emplace_back(env);
    if (search.builtin_directory != nullptr) directories.emplace_back(search.builtin_directory);
    for (const auto& dir : directories)
        if (fs::is_regular_file(dir / file_name)) return dir / file_name;
    throw InputError(name_or_path, search.field, std::string("no such file, and not a shipped name (") + search.hint + ")");
}

}  // namespace pp5
