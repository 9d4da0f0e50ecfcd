#include "scene/volume/sample_decode.h"

#include "scene/volume/byte_fields.h"
#include "scene/volume/load_checks.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>

namespace pp5::volume_detail {

namespace {

// `stored` is the value in the file, `value` what scaling made of it.
[[noreturn]] void reject(const std::string& file, glm::ivec3 dims, std::size_t i, double stored, double value,
                         bool scaled) {
    const auto nx = static_cast<std::size_t>(dims.x);
    const auto ny = static_cast<std::size_t>(dims.y);
    const std::string where = fmt::format("sample at voxel ({}, {}, {})", i % nx, (i / nx) % ny, i / (nx * ny));
    if (std::isnan(stored)) throw InputError(file, "voxel data", where + " is NaN");
    if (std::isinf(stored)) throw InputError(file, "voxel data", where + " is infinite");
    throw InputError(file, "voxel data",
                     fmt::format("{} is {}{}, beyond the float32 range samples are held in", where, value,
                                 scaled ? " after scl_slope/scl_inter" : ""));
}

template <class T>
void decode(std::span<const std::byte> bytes, const SampleEncoding& e, glm::ivec3 dims, const std::string& file,
            std::vector<float>& out) {
    const bool scaled = !(e.slope == 1.0 && e.intercept == 0.0);
    const std::byte* p = bytes.data();
    for (std::size_t i = 0; i < out.size(); ++i, p += sizeof(T)) {
        const T stored = read_field<T>(p, e.order);
        if (!scaled && !std::is_floating_point_v<T>) {
            // Unscaled integers are always finite and within float range: the common case, kept lean.
            out[i] = static_cast<float>(stored);
            continue;
        }
        const double value = scaled ? e.slope * static_cast<double>(stored) + e.intercept : static_cast<double>(stored);
        const auto sample = static_cast<float>(value);
        if (!std::isfinite(sample)) reject(file, dims, i, static_cast<double>(stored), value, scaled);
        out[i] = sample;
    }
}

}  // namespace

std::vector<float> decode_samples(std::span<const std::byte> bytes, const SampleEncoding& encoding, glm::ivec3 dims,
                                  const std::string& file) {
    const std::size_t count = voxel_count(dims);
    if (bytes.size() != count * scalar_size_bytes(encoding.type))
        throw std::logic_error("decode_samples: byte count does not match dims and type");
    std::vector<float> out(count);
    switch (encoding.type) {
        case ScalarType::UInt8: decode<std::uint8_t>(bytes, encoding, dims, file, out); break;
        case ScalarType::Int8: decode<std::int8_t>(bytes, encoding, dims, file, out); break;
        case ScalarType::UInt16: decode<std::uint16_t>(bytes, encoding, dims, file, out); break;
        case ScalarType::Int16: decode<std::int16_t>(bytes, encoding, dims, file, out); break;
        case ScalarType::UInt32: decode<std::uint32_t>(bytes, encoding, dims, file, out); break;
        case ScalarType::Int32: decode<std::int32_t>(bytes, encoding, dims, file, out); break;
        case ScalarType::Float32: decode<float>(bytes, encoding, dims, file, out); break;
        case ScalarType::Float64: decode<double>(bytes, encoding, dims, file, out); break;
    }
    return out;
}

}  // namespace pp5::volume_detail
