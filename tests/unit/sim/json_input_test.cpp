// User JSON nested beyond any file pp5sim writes is refused while it is parsed, before anything walks it
// recursively (a document tens of thousands deep would overflow the stack); malformed JSON names the file.

#include "sim/core/json_input.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <string>

namespace pp5 {
namespace {

TEST(JsonInput, DeepNestingIsRefusedNamingTheFileAndField) {
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    try {
        (void)parse_json_input(deep, "shard-0-of-2.json", "shard");
        FAIL() << "accepted JSON 100000 deep";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "shard-0-of-2.json");
        EXPECT_EQ(e.field(), "shard");
        EXPECT_NE(std::string(e.what()).find("more than 128 deep"), std::string::npos) << e.what();
    }
    const std::string objects = [] {
        std::string s;
        for (int i = 0; i < 5000; ++i) s += "{\"a\":";
        s += "1";
        for (int i = 0; i < 5000; ++i) s += "}";
        return s;
    }();
    EXPECT_THROW((void)parse_json_input(objects, "stats.json", "compare"), InputError);
}

TEST(JsonInput, DocumentsWithinTheLimitParseAsBefore) {
    const std::string at_limit = std::string(128, '[') + std::string(128, ']');
    EXPECT_NO_THROW((void)parse_json_input(at_limit, "f", "x"));
    EXPECT_THROW((void)parse_json_input(std::string(129, '[') + std::string(129, ']'), "f", "x"), InputError);
    const nlohmann::json j = parse_json_input(R"({"frames": [{"simulated_seconds": 0.5}]})", "f", "x");
    EXPECT_EQ(j["frames"][0]["simulated_seconds"].get<double>(), 0.5);
    try {
        (void)parse_json_input("{\"a\": ", "run/stats.json", "compare");
        FAIL() << "accepted truncated JSON";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "run/stats.json");
        EXPECT_NE(std::string(e.what()).find("is not JSON"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pp5
