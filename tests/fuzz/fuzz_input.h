#pragma once
// What every fuzzing harness shares: the scratch file an input is written to (the loaders read files,
// as the CLI does), and the verdict on what a loader does with it.
//
// A loader may refuse an input only with InputError: the one-line refusal naming file, field and
// reason that the CLI turns into exit code 2. Any other exception escapes the harness and aborts the
// run, and libFuzzer (or the replay driver) reports it as a finding, as it does a crash, a sanitizer
// report, a hang or a run past its memory limit.

#include "sim/core/input_error.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace pp5::fuzz {

// A directory of this process's own under the temporary directory, so harnesses run side by side
// (libFuzzer's -jobs, ctest -j) never share a file.
inline const std::filesystem::path& scratch_directory() {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::temp_directory_path() / ("pp5-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

// Writes the input as the file `name` in the scratch directory and returns its path.
inline std::filesystem::path write_scratch(std::string_view name, const std::uint8_t* data, std::size_t size) {
    const auto path = scratch_directory() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path;
}

// Runs one input through a loader: accepted or refused as input are both fine.
template <class Load>
int refused_only_as_input(Load&& load) {
    try {
        load();
    } catch (const InputError&) {}
    return 0;
}

}  // namespace pp5::fuzz
