#pragma once
// Checks every volume loader shares, so that the same problem reads the same way whichever format it
// turns up in. Internal to scene/volume.

#include "scene/volume/host_memory.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <string>

namespace pp5::volume_detail {

// Far beyond any scanner's output; a larger value is a corrupt header, not a volume to try to allocate.
inline constexpr long long kMaxAxisVoxels = 4096;

// Throws InputError(file, "file", ...) unless `path` names an existing regular file (or a link to one).
void require_regular_file(const std::filesystem::path& path);

// Throws InputError(file, field, ...) unless 1 <= value <= kMaxAxisVoxels.
void check_axis_size(const std::string& file, const std::string& field, long long value);

// Throws InputError(file, field, ...) unless value lies in [1e-6, 1e6]: positive, finite, and far from
// what would overflow or underflow the renderers' arithmetic.
void check_spacing(const std::string& file, const std::string& field, double value);

std::size_t voxel_count(glm::ivec3 dims);

std::string dims_text(glm::ivec3 dims);  // "10x10x11"

// "file holds 1000 bytes of voxel data but dims 10x10x11 of int16 need 2200"
std::string size_mismatch(std::size_t held_bytes, glm::ivec3 dims, ScalarType type);

}  // namespace pp5::volume_detail
