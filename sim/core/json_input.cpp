#include "sim/core/json_input.h"

#include "sim/core/host_memory.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <fstream>

namespace pp5 {

namespace {

// Thrown from the parser's callback to stop it at the first level too deep.
struct TooDeep {};

nlohmann::json::parser_callback_t depth_limit(int most_depth) {
    return [most_depth](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if ((event == nlohmann::json::parse_event_t::object_start ||
             event == nlohmann::json::parse_event_t::array_start) &&
            depth >= most_depth)
            throw TooDeep{};
        return true;
    };
}

template <class Input>
nlohmann::json parse_limited(Input&& input, const std::string& file, const std::string& field, int most_depth) {
    try {
        return nlohmann::json::parse(std::forward<Input>(input), depth_limit(most_depth));
    } catch (const TooDeep&) {
        throw InputError(
            file, field,
            fmt::format("nests arrays and objects more than {} deep: not a file pp5sim writes", most_depth));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(file, field, std::string("is not JSON: ") + e.what());
    }
}

}  // namespace

nlohmann::json parse_json_input(const std::string& text, const std::string& file, const std::string& field,
                                int most_depth) {
    return parse_limited(text, file, field, most_depth);
}

nlohmann::json read_json_file(const std::filesystem::path& path, const std::string& field, std::uintmax_t most_bytes,
                              int most_depth) {
    const std::string file = path.string();
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(path, error);
    if (error) throw InputError(file, field, "cannot be read: " + error.message());
    if (bytes > most_bytes)
        throw InputError(file, field,
                         fmt::format("is {:.1f} MB, more than the {:.1f} MB such a file can be",
                                     static_cast<double>(bytes) / 1e6, static_cast<double>(most_bytes) / 1e6));
    constexpr double kParsedBytesPerFileByte = 10;
    check_fits_host_memory(file, field, kParsedBytesPerFileByte * static_cast<double>(bytes),
                           fmt::format("parsing a {:.1f} MB JSON file", static_cast<double>(bytes) / 1e6));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(file, field, "cannot be opened");
    return parse_limited(in, file, field, most_depth);
}

}  // namespace pp5
