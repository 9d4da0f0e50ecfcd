#pragma once
// Reading a number from a file's bytes in the file's byte order, whatever the host's. Internal to
// scene/volume.

#include <array>
#include <bit>
#include <cstddef>
#include <cstring>
#include <span>
#include <utility>

namespace pp5::volume_detail {

// The caller guarantees p points at sizeof(T) readable bytes.
template <class T>
T read_field(const std::byte* p, std::endian order) {
    std::array<std::byte, sizeof(T)> raw;
    std::memcpy(raw.data(), p, sizeof(T));
    if (order != std::endian::native) {
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
    return std::bit_cast<T>(raw);
}

template <class T>
T read_field(std::span<const std::byte> bytes, std::size_t offset, std::endian order) {
    return read_field<T>(bytes.data() + offset, order);
}

}  // namespace pp5::volume_detail
