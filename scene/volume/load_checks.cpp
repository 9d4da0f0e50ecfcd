#include "scene/volume/load_checks.h"

#include "sim/core/host_memory.h"

#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <cmath>
#include <system_error>

namespace pp5::volume_detail {

void require_regular_file(const std::filesystem::path& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found)
        throw InputError(path.string(), "file", "does not exist");
    if (ec) throw InputError(path.string(), "file", "cannot be examined: " + ec.message());
    if (status.type() == std::filesystem::file_type::directory)
        throw InputError(path.string(), "file", "is a directory, not a volume file");
    if (status.type() != std::filesystem::file_type::regular)
        throw InputError(path.string(), "file", "is not a regular file");
}

void check_axis_size(const std::string& file, const std::string& field, long long value) {
    if (value < 1) throw InputError(file, field, fmt::format("is {}: every axis needs at least 1 voxel", value));
    if (value > kMaxAxisVoxels) {
        throw InputError(file, field,
                         fmt::format("is {}: more than the {} voxels per axis a volume may have (corrupt header?)",
                                     value, kMaxAxisVoxels));
    }
}

void check_spacing(const std::string& file, const std::string& field, double value) {
    // Beyond these the products and inverses the renderers take of it overflow or underflow a float.
    constexpr double kFinest = 1e-6, kCoarsest = 1e6;
    if (!(std::isfinite(value) && value >= kFinest && value <= kCoarsest))
        throw InputError(
            file, field,
            fmt::format("is {}: a voxel spacing must lie from {} to {} (in the file's units, mm for scans)", value,
                        kFinest, kCoarsest));
}

std::size_t voxel_count(glm::ivec3 dims) {
    return static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
}

std::string dims_text(glm::ivec3 dims) { return fmt::format("{}x{}x{}", dims.x, dims.y, dims.z); }

std::string size_mismatch(std::size_t held_bytes, glm::ivec3 dims, ScalarType type) {
    return fmt::format("file holds {} bytes of voxel data but dims {} of {} need {}", held_bytes, dims_text(dims),
                       to_string(type), voxel_count(dims) * scalar_size_bytes(type));
}

}  // namespace pp5::volume_detail

namespace pp5 {

void check_volume_fits_host(const std::string& file, const std::string& field, glm::ivec3 dims, ScalarType type) {
    const double needed = static_cast<double>(volume_detail::voxel_count(dims)) *
                          static_cast<double>(scalar_size_bytes(type) + sizeof(float));
    check_fits_host_memory(file, field, needed,
                           fmt::format("loading a {} volume of {}", volume_detail::dims_text(dims), to_string(type)));
}

}  // namespace pp5
