// InVesalius .inv3 projects: the gzip stream, the tar headers, main.plist's XML and the matrix it names.
#include "scene/volume/inv3_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("input.inv3", data, size);
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_inv3(path); });
}
