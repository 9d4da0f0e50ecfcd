// Calibration target files: rows, their scenarios, machines, frames, metrics and formulas, checked as
// `pp5sim fit` and `reproduce` check them before rendering anything.
#include "calibration/targets.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("targets.toml", data, size);
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_targets(path); });
}
