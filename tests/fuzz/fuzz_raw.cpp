// Headerless raw volumes: the layout a user gives on the command line (dimensions, sample type, byte
// order, header bytes, spacing) against the file's real size and contents. The input's first 16 bytes
// choose the layout; the rest is the file.
#include "scene/volume/volume_io.h"
#include "tests/fuzz/fuzz_input.h"

#include <cmath>
#include <cstring>
#include <iterator>

namespace {

constexpr std::size_t kLayoutBytes = 16;

template <class T>
T take(const std::uint8_t* at) {
    T value;
    std::memcpy(&value, at, sizeof value);
    return value;
}

pp5::RawLayout layout_from(const std::uint8_t* b) {
    pp5::RawLayout layout;
    // Signed 16-bit sizes, so zero, negative and huge dimensions all come up.
    layout.dims = {take<std::int16_t>(b), take<std::int16_t>(b + 2), take<std::int16_t>(b + 4)};
    constexpr pp5::ScalarType kTypes[] = {pp5::ScalarType::UInt8,   pp5::ScalarType::Int8,   pp5::ScalarType::UInt16,
                                          pp5::ScalarType::Int16,   pp5::ScalarType::UInt32, pp5::ScalarType::Int32,
                                          pp5::ScalarType::Float32, pp5::ScalarType::Float64};
    layout.type = kTypes[b[6] % std::size(kTypes)];
    layout.big_endian = (b[7] & 1) != 0;
    layout.header_bytes = take<std::uint16_t>(b + 8);
    // One byte per axis as a power of two from 2^-64 to 2^63, so out-of-range spacings come up too.
    for (int axis = 0; axis < 3; ++axis)
        layout.spacing[axis] = std::ldexp(1.0f, static_cast<int>(b[10 + axis] % 128) - 64);
    return layout;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < kLayoutBytes) return 0;
    const pp5::RawLayout layout = layout_from(data);
    const auto path = pp5::fuzz::write_scratch("input.raw", data + kLayoutBytes, size - kLayoutBytes);
    return pp5::fuzz::refused_only_as_input([&] { pp5::load_raw(path, layout); });
}
