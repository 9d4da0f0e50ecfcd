#pragma once
// A test's scratch folder.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

namespace pp5::test {

// A directory of its own for each test, removed afterwards; named by test and process so that
// tests run in parallel (ctest -j) never share files.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string leaf =
            std::string("pp5_test_") + info->test_suite_name() + "_" + info->name() + "_" + std::to_string(::getpid());
        for (char& c : leaf) {
            if (c == '/') c = '_';
        }
        path_ = std::filesystem::temp_directory_path() / leaf;
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

}  // namespace pp5::test
