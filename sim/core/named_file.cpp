#include "sim/core/named_file.h"

#include "sim/core/input_error.h"
#include "sim/core/spelling.h"

#include <fmt/format.h>

#include <cstdlib>
#include <map>
#include <string_view>
#include <vector>

namespace pp5 {

std::filesystem::path resolve_named_file(const std::string& name_or_path, const NamedFileSearch& search) {
    namespace fs = std::filesystem;
    // A path that exists but cannot be followed (a symlink loop, a folder without permission) is the
    // user's to fix; a missing one may be a shipped name.
    std::error_code error;
    const fs::file_status status = fs::status(name_or_path, error);
    if (!error && fs::is_regular_file(status)) return name_or_path;
    if (error && error != std::errc::no_such_file_or_directory && error != std::errc::not_a_directory)
        throw InputError(name_or_path, search.field, "cannot be read: " + error.message());
    const std::string file_name = name_or_path + ".toml";
    std::vector<fs::path> directories;
    if (const char* env = std::getenv(search.environment_variable)) directories.emplace_back(env);
    if (search.builtin_directory != nullptr) directories.emplace_back(search.builtin_directory);
    for (const auto& dir : directories)
        if (fs::is_regular_file(dir / file_name, error)) return dir / file_name;
    // A slip in a shipped name gets the name it was probably meant to be.
    std::vector<std::string> names;
    for (const fs::path& file : list_named_files(search)) names.push_back(file.stem().string());
    throw InputError(
        name_or_path, search.field,
        std::string("no such file, and not a shipped name (") + search.hint + ")" + did_you_mean(name_or_path, names));
}

std::vector<std::filesystem::path> list_named_files(const NamedFileSearch& search) {
    namespace fs = std::filesystem;
    std::vector<fs::path> directories;
    if (const char* env = std::getenv(search.environment_variable)) directories.emplace_back(env);
    if (search.builtin_directory != nullptr) directories.emplace_back(search.builtin_directory);
    std::map<std::string, fs::path> by_name;
    for (const auto& dir : directories) {
        std::error_code error;
        for (fs::directory_iterator it(dir, error), end; !error && it != end; it.increment(error))
            if (std::error_code unreadable; it->path().extension() == ".toml" && it->is_regular_file(unreadable))
                by_name.emplace(it->path().stem().string(), it->path());
    }
    std::vector<fs::path> out;
    for (auto& [name, path] : by_name) out.push_back(std::move(path));
    return out;
}

std::string output_name_problem(const std::string& name) {
    constexpr std::size_t kLongestOutputName = 100;
    if (name.empty() || name.size() > kLongestOutputName || name == "." || name == ".." ||
        name.find_first_of(std::string_view("/\\\0", 3)) != std::string::npos)
        return fmt::format(
            "must be a name of 1 to {} characters without slashes, and not . or .. (it names an output folder)",
            kLongestOutputName);
    return {};
}

}  // namespace pp5
