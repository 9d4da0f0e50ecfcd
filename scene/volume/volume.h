#pragma once
// A scalar volume on a regular grid: the input of every rendering kernel.
//
// Samples are held as float whatever the source type, so kernels share one code path; the source
// type and value range are kept because the simulated machine stores voxels at the source's width.
// Index order is x fastest, then y, then z (the order of NIfTI, raw and .den files).

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pp5 {

enum class ScalarType : std::uint8_t { UInt8, Int8, UInt16, Int16, UInt32, Int32, Float32, Float64 };

std::string_view to_string(ScalarType type);
std::optional<ScalarType> parse_scalar_type(std::string_view name);  // "uint8", "int16", "float32", ...
std::size_t scalar_size_bytes(ScalarType type);
inline bool is_integer_type(ScalarType type) { return type != ScalarType::Float32 && type != ScalarType::Float64; }

class Volume {
public:
    Volume() = default;
    // Throws std::invalid_argument if samples.size() != dims.x*dims.y*dims.z, a dimension < 1 or a
    // spacing is not positive and finite (kernels divide by it).
    Volume(glm::ivec3 dims, glm::vec3 spacing, ScalarType source_type, std::vector<float> samples,
           std::string name = {});

    glm::ivec3 dims() const { return dims_; }
    glm::vec3 spacing() const { return spacing_; }  // physical size of a voxel (mm)
    glm::vec3 physical_extent() const;              // dims * spacing
    ScalarType source_type() const { return source_type_; }
    const std::string& name() const { return name_; }
    void set_name(std::string name) { name_ = std::move(name); }
    float min_value() const { return min_value_; }
    float max_value() const { return max_value_; }
    std::size_t voxel_count() const { return samples_.size(); }

    std::size_t index(int x, int y, int z) const {
        return static_cast<std::size_t>(x) +
               static_cast<std::size_t>(dims_.x) *
                   (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(z));
    }
    float at(int x, int y, int z) const { return samples_[index(x, y, z)]; }
    // Clamps coordinates to the grid: the boundary rule for gradients and interpolation.
    float at_clamped(int x, int y, int z) const;
    std::span<const float> samples() const { return samples_; }

private:
    glm::ivec3 dims_{0};
    glm::vec3 spacing_{1.0f};
    ScalarType source_type_ = ScalarType::Float32;
    std::vector<float> samples_;
    std::string name_;
    float min_value_ = 0.0f;
    float max_value_ = 0.0f;
};

}  // namespace pp5
