// UNC .den (VolPack's density files, gzipped or not): the 62-byte header in either byte order and the
// samples it declares.
#include "scene/volume/volume_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("input.den", data, size);
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_den(path); });
}
