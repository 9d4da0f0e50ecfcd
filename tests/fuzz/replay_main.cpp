// The driver for builds without libFuzzer (GCC, or any build without -DPP5_FUZZ=ON): runs each file
// named on the command line, or every file in each directory named, through the harness once. This is
// how the suite replays the seed corpora and any input a fuzzing run found; a finding aborts as it
// would under libFuzzer.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

void run_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (!in.good() && !in.eof()) throw std::runtime_error("cannot read " + path.string());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: " << argv[0] << " FILE_OR_DIRECTORY...\n";
        return 2;
    }
    std::size_t inputs = 0;
    for (int i = 1; i < argc; ++i) {
        const std::filesystem::path arg(argv[i]);
        std::set<std::filesystem::path> files;  // in name order, so a run is the same every time
        if (std::filesystem::is_directory(arg)) {
            for (const auto& entry : std::filesystem::directory_iterator(arg))
                if (entry.is_regular_file()) files.insert(entry.path());
        } else {
            files.insert(arg);
        }
        for (const auto& file : files) {
            run_file(file);
            ++inputs;
        }
    }
    if (inputs == 0) {
        std::cerr << "no inputs found\n";
        return 2;
    }
    std::cout << inputs << " inputs run, none a finding\n";
    return 0;
}
