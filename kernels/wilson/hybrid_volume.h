#pragma once
// Wilson, Ma and McCormick's hybrid representation, made from a full-resolution volume once, before any
// frame: a low-resolution copy L (one sample per k^3 voxels), and a point wherever L's trilinear
// reconstruction misses the original by more than a threshold, sampled on an error grid.
//
// Grids share one extent: low-resolution sample j sits at original coordinate (j + 1/2) k - 1/2 on
// each axis, and error-grid sample i at (i + 1/2) / g - 1/2 (g samples per voxel), so every sample is
// the centre of the cell it stands for.
//
// A point is stored as the paper stores it: its error-grid position (one byte an axis when the grid is
// at most 256 along every axis, else two), a normal index, its error and the original value there.
// Two additions, each sized where it applies: the value takes two bytes when the source has more than
// 8 bits (the paper's data are bytes), and a byte of gradient magnitude is kept when the scenario's
// classification weights opacity by it (Levoy's functions do; the paper's palettes do not).

#include "kernels/wilson/wilson_settings.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace pp5 {

// 255 directions spread evenly over the sphere (a spherical Fibonacci lattice), and index 255 for a
// zero gradient: the paper's "normal vectors uniformly distributed in 3-space", one byte each.
class NormalTable {
public:
    static constexpr int kDirections = 255;
    static constexpr std::uint8_t kNone = 255;
    static const NormalTable& get();
    glm::vec3 direction(std::uint8_t index) const { return index == kNone ? glm::vec3(0.0f) : directions_[index]; }
    // The direction nearest a normal (kNone for a zero vector).
    std::uint8_t nearest(glm::vec3 normal) const;

private:
    NormalTable();
    std::array<glm::vec3, kDirections> directions_;
};

// A point record's layout.
struct PointFormat {
    int coordinate_bytes = 1;  // per axis
    int value_bytes = 1;
    bool gradient_byte = false;
    // Coordinates, the value, a normal index and the error (and the gradient byte).
    int record_bytes() const { return 3 * coordinate_bytes + value_bytes + 2 + (gradient_byte ? 1 : 0); }
    // The paper's: 8-bit coordinates for error grids up to 256 along every axis, else 16.
    static PointFormat for_grid(glm::ivec3 error_grid, int value_bytes, bool gradient_byte);
};

// A representation's size as the paper counts it (section 3.3): each low-resolution voxel a value and a
// one-byte normal index, each point its record; megabytes of 10^6 bytes.
struct HybridStorage {
    glm::ivec3 low_resolution{0};
    int voxel_value_bytes = 1;
    bool voxel_gradient_byte = false;
    std::uint64_t points = 0;
    PointFormat point_format;

    std::uint64_t voxel_bytes() const {
        return static_cast<std::uint64_t>(voxel_value_bytes + 1 + (voxel_gradient_byte ? 1 : 0));
    }
    std::uint64_t volume_bytes() const;
    std::uint64_t point_bytes() const { return points * static_cast<std::uint64_t>(point_format.record_bytes()); }
    std::uint64_t total_bytes() const { return volume_bytes() + point_bytes(); }
};

// One point as stored.
struct HybridPoint {
    std::uint16_t x = 0, y = 0, z = 0;  // error-grid sample
    std::uint16_t value = 0;            // quantized over the source's value range
    std::uint8_t normal = NormalTable::kNone;
    std::int8_t error = 0;      // the error, in 127ths of the value range
    std::uint8_t gradient = 0;  // quantized over [0, the largest point gradient]
};

// The thresholds the paper uses, as shares of the value range (sections 3.1 and 5).
inline constexpr std::array<double, 5> kPaperThresholds = {1.0 / 64, 1.0 / 32, 1.0 / 16, 1.0 / 12, 1.0 / 8};

// What point selection saw.
struct PointSelection {
    std::array<std::uint64_t, 5> at_paper_thresholds{};  // samples past each of kPaperThresholds (same sign rule)
    std::uint64_t error_samples = 0;                     // error-grid samples examined
    std::uint64_t above_threshold = 0;                   // of those, past the threshold (before max_points)
    std::uint64_t underestimates = 0;                    // of those, where L was too low
    double largest_error = 0;                            // |e|, as a share of the value range
    double mean_abs_error = 0;                           // over every error sample
};

class HybridVolume {
public:
    // Makes the representation. `gradient_byte`: keep each point's gradient magnitude (for
    // classifications that use it). Throws InputError (field "wilson.*") when the error grid would be
    // too large to examine.
    static HybridVolume build(const Volume& original, const WilsonSettings& settings, bool gradient_byte);

    const Volume& low_resolution() const { return low_; }
    int factor() const { return factor_; }
    glm::ivec3 error_grid() const { return grid_; }
    int error_grid_factor() const { return grid_factor_; }
    std::span<const HybridPoint> points() const { return points_; }
    const PointFormat& point_format() const { return format_; }
    const PointSelection& selection() const { return selection_; }
    HybridStorage storage() const;

    // A point's fields decoded: position in original voxel coordinates, value, error and gradient
    // magnitude in value units (per voxel for the gradient).
    glm::vec3 position(const HybridPoint& p) const;
    float value(const HybridPoint& p) const;
    float error(const HybridPoint& p) const;
    float gradient_magnitude(const HybridPoint& p) const;

private:
    Volume low_;
    int factor_ = 1;
    glm::ivec3 grid_{0};
    int grid_factor_ = 1;
    float value_min_ = 0, value_range_ = 0, gradient_max_ = 0;
    std::vector<HybridPoint> points_;
    PointFormat format_;
    PointSelection selection_;
};

// L's trilinear reconstruction at an original-voxel position (what the slices show there).
float reconstruct_low_resolution(const Volume& low, int factor, glm::vec3 position);

}  // namespace pp5
