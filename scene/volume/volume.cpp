#include "scene/volume/volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pp5 {

namespace {

struct ScalarTypeInfo {
    ScalarType type;
    std::string_view name;
    std::size_t bytes;
};

// One table so names, sizes and parsing cannot drift apart.
constexpr std::array<ScalarTypeInfo, 8> kScalarTypes{{
    {ScalarType::UInt8, "uint8", 1},
    {ScalarType::Int8, "int8", 1},
    {ScalarType::UInt16, "uint16", 2},
    {ScalarType::Int16, "int16", 2},
    {ScalarType::UInt32, "uint32", 4},
    {ScalarType::Int32, "int32", 4},
    {ScalarType::Float32, "float32", 4},
    {ScalarType::Float64, "float64", 8},
}};

const ScalarTypeInfo& info(ScalarType type) {
    for (const auto& entry : kScalarTypes) {
        if (entry.type == type) return entry;
    }
    throw std::invalid_argument("unknown ScalarType value " + std::to_string(static_cast<int>(type)));
}

}  // namespace

std::string_view to_string(ScalarType type) { return info(type).name; }

std::size_t scalar_size_bytes(ScalarType type) { return info(type).bytes; }

std::optional<ScalarType> parse_scalar_type(std::string_view name) {
    for (const auto& entry : kScalarTypes) {
        if (entry.name == name) return entry.type;
    }
    // The C spellings people type on a command line.
    if (name == "float") return ScalarType::Float32;
    if (name == "double") return ScalarType::Float64;
    return std::nullopt;
}

Volume::Volume(glm::ivec3 dims, glm::vec3 spacing, ScalarType source_type, std::vector<float> samples, std::string name)
    : dims_(dims), spacing_(spacing), source_type_(source_type), samples_(std::move(samples)), name_(std::move(name)) {
    if (dims.x < 1 || dims.y < 1 || dims.z < 1) {
        throw std::invalid_argument("Volume: every dimension must be at least 1, got " + std::to_string(dims.x) + "x" +
                                    std::to_string(dims.y) + "x" + std::to_string(dims.z));
    }
    const std::size_t expected =
        static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
    if (samples_.size() != expected) {
        throw std::invalid_argument("Volume: " + std::to_string(samples_.size()) + " samples for dims needing " +
                                    std::to_string(expected));
    }
    for (int axis = 0; axis < 3; ++axis) {
        if (!(std::isfinite(spacing[axis]) && spacing[axis] > 0.0f)) {
            throw std::invalid_argument("Volume: spacing must be positive and finite, got " +
                                        std::to_string(spacing[axis]) + " on axis " + std::to_string(axis));
        }
    }
    // NaN samples (possible only for volumes built in code; the loaders reject them) are left out of
    // the range, so one bad sample cannot poison every transfer function built from min/max.
    float lo = std::numeric_limits<float>::infinity();
    float hi = -std::numeric_limits<float>::infinity();
    for (const float v : samples_) {
        if (v < lo) lo = v;
        if (v > hi) hi = v;
    }
    if (lo <= hi) {
        min_value_ = lo;
        max_value_ = hi;
    }
}

glm::vec3 Volume::physical_extent() const { return glm::vec3(dims_) * spacing_; }

float Volume::at_clamped(int x, int y, int z) const {
    return at(std::clamp(x, 0, dims_.x - 1), std::clamp(y, 0, dims_.y - 1), std::clamp(z, 0, dims_.z - 1));
}

}  // namespace pp5
