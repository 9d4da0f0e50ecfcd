#include "sim/core/json_input.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

namespace pp5 {

namespace {

// Thrown from the parser's callback to stop it at the first level too deep.
struct TooDeep {};

}  // namespace

nlohmann::json parse_json_input(const std::string& text, const std::string& file, const std::string& field, int most_depth) {
    const nlohmann::json::parser_callback_t limit = [most_depth](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if ((event == nlohmann::json::parse_event_t::object_start || event == nlohmann::json::parse_event_t::array_start) &&
            depth >= most_depth)
            throw TooDeep{};
        return true;
    };
    try {
        return nlohmann::json::parse(text, limit);
    } catch (const TooDeep&) {
        throw InputError(file, field, fmt::format("nests arrays and objects more than {} deep: not a file pp5sim writes", most_depth));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(file, field, std::string("is not JSON: ") + e.what());
    }
}

}  // namespace pp5
