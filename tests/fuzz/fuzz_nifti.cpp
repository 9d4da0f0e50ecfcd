// NIfTI-1 (.nii, gzipped or not): the header's every field, gzip streams cut short or inflating far
// beyond their size, samples that are NaN or do not match the header.
#include "scene/volume/volume_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = pp5::fuzz::write_scratch("input.nii", data, size);
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_nifti(path); });
}
