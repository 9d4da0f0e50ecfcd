#pragma once
// Where the project's sources are (shipped scenarios, machine files, golden records), for the tests
// that read them. The path is compiled into one generated file (tests/CMakeLists.txt) rather than
// onto every test's compile line, so that the other test objects of a second clone are ccache hits.

#include <filesystem>

namespace pp5::test {

std::filesystem::path source_dir();

}  // namespace pp5::test
