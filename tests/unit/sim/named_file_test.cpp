#include "sim/core/named_file.h"
#include "sim/core/input_error.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

class NamedFile : public ::testing::Test {
protected:
    void SetUp() override { std::ofstream(dir / "sphere.toml") << "# a preset\n"; }
    std::string why(const std::string& name) const {
        const NamedFileSearch search{"PP5_NAMED_FILE_TEST_UNSET", dir_text.c_str(), "scenario", "the test's folder"};
        try {
            resolve_named_file(name, search);
        } catch (const InputError& e) {
            return e.reason();
        }
        return "found";
    }
    test::TempDir scratch;
    fs::path dir = scratch.path();
    std::string dir_text = dir.string();
};

TEST_F(NamedFile, APresetByNameAMissOnlyWithASuggestionAndALoopAsUnreadable) {
    EXPECT_EQ(why("sphere"), "found");
    EXPECT_NE(why("spere").find("did you mean sphere?"), std::string::npos) << why("spere");
    const fs::path loop = dir / "loop";
    fs::create_symlink(loop, loop);
    EXPECT_NE(why(loop.string()).find("cannot be read"), std::string::npos) << why(loop.string());
}

}  // namespace
}  // namespace pp5
