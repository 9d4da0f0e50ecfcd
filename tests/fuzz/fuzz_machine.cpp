// Machine files: TOML syntax and nesting, [machine], and every parameter group of the machine and the
// registered kernels (names, types, ranges), resolved as `render --machine FILE` resolves them.
#include "kernels/registry/run_config.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("machine.toml", data, size);
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_run_config(path.string(), {}); });
}
