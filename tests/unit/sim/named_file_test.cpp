#include "sim/core/input_error.h"
#include "sim/core/named_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

class NamedFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir = dir_text;
        fs::remove_all(dir);
        fs::create_directories(dir);
        std::ofstream(dir / "sphere.toml") << "# a preset\n";
    }
    std::string why(const std::string& name) const {
        const NamedFileSearch search{"PP5_NAMED_FILE_TEST_UNSET", dir_text.c_str(), "scenario", "the test's folder"};
        try {
            resolve_named_file(name, search);
        } catch (const InputError& e) {
            return e.reason();
        }
        return "found";
    }
    fs::path dir;
    // Each test process its own folder: ctest -j runs this fixture's tests side by side.
    std::string dir_text = (fs::temp_directory_path() / ("pp5_named_file_test_" + std::to_string(::getpid()))).string();
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
