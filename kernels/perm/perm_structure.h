#pragma once
// Lim and Shin's PERM (Precomputed density and gRadient Map), built once from a volume and a
// classification: the candidate cells (those that may be non-transparent), an index volume pointing
// at each candidate's record, and per record the density at D^3 quantized positions (the Density
// Buffer), and the gradient at G^3 (three magnitude bytes, the Gradient Buffer, and their signs, the
// Sign Buffer). A ray sample finds its cell through the index volume and its quantized position
// through three one-dimensional mapping tables (M_LUT), and reads the values there instead of
// interpolating them.
//
// Sizes follow the paper's eqs. (3) and (6): S b_iv for the index volume (plus a 4-byte summed count
// per z slice when b_iv = 2) and N_cc (D^3 b_db + G^3 (3 b_gb + b_sb)) for the records, MB = 10^6 B.

#include "kernels/perm/perm_settings.h"
#include "scene/render/classification.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace pp5 {

struct GradientField;

// The paper's memory equations, for any data set.
struct PermMemory {
    glm::ivec3 dims{0};                       // the volume: S = x y z
    std::uint64_t candidates = 0;             // N_cc
    int density_positions = 5;                // D
    int gradient_positions = 5;               // G
    int index_bytes = 2;                      // b_iv
    int density_bytes = 1;                    // b_db (the source's sample size: 1 for 8-bit data)
    static constexpr int kGradientBytes = 1;  // b_gb: each magnitude in a byte
    static constexpr int kSignBytes = 1;      // b_sb: two bits per axis

    std::uint64_t index_volume_bytes() const;
    std::uint64_t summed_table_bytes() const;  // 4 bytes per z slice with 2-byte indices, else none
    std::uint64_t record_bytes() const;        // one candidate cell's
    std::uint64_t total_bytes() const;
};

// One axis's mapping table: a fraction's QBM-th, to a quantized position (see PermSettings).
class PositionTable {
public:
    PositionTable(int positions, int qbm, QuantizedPositions rule);
    int positions() const { return positions_; }
    // The position index for a fraction in [0, 1); under the paper's rule it can be `positions`.
    int index(float fraction) const;
    // Where position k sits in the cell, in [0, 1].
    double offset(int k) const;
    int at(int qi) const { return table_[static_cast<std::size_t>(qi)]; }

private:
    int positions_;
    int qbm_;
    QuantizedPositions rule_;
    std::vector<int> table_;
};

class PermStructure {
public:
    static constexpr std::int32_t kNull = -1;

    // Throws InputError (perm.index_bytes) when a z slice holds more candidates than 2-byte indices
    // can number.
    // `before_records` sees the candidates and the memory they will need before any record is made,
    // and may refuse (throw) so that nothing too large is allocated.
    using FitCheck = std::function<void(const PermMemory&, const std::vector<glm::ivec3>& cell_origins)>;
    static PermStructure build(const Volume& volume, const Classification& classification, const PermSettings& settings,
                               const FitCheck& before_records = {});

    std::uint64_t candidates() const { return cell_origin_.size(); }
    std::uint64_t candidates_before_reduction() const { return unreduced_; }
    // The candidate index of the cell whose origin is voxel (x, y, z), or kNull.
    std::int32_t index(int x, int y, int z) const { return index_[volume_index(x, y, z)]; }
    glm::ivec3 cell_origin(std::uint32_t candidate) const { return cell_origin_[candidate]; }
    PermMemory memory() const { return memory_; }
    // The quantized density and gradient a sample at `position` (voxel coordinates, within the cell
    // whose origin is `cell`) reads from candidate `candidate`; `carried` counts lookups whose
    // paper-rule index carried past the cell's last position.
    struct Sample {
        float value = 0;
        glm::vec3 gradient{0.0f};
    };
    Sample lookup(std::uint32_t candidate, glm::vec3 fraction, std::uint64_t* carried = nullptr) const;
    // The density position (0 .. D^3 - 1) a sample at `fraction` of its cell reads, as lookup() does.
    int density_position(glm::vec3 fraction, std::uint64_t* carried = nullptr) const {
        return combined(density_table_, fraction, carried);
    }
    // What the record holds at density position `position`: its density, and the gradient of the
    // gradient position whose sub-cube holds it (the same position when D = G). What the PPs shade.
    Sample at_density_position(std::uint32_t candidate, int position) const;
    float density_at(std::uint32_t candidate, int position) const {
        const std::size_t dn = static_cast<std::size_t>(density_positions_per_record());
        return value_min_ + static_cast<float>(density_[candidate * dn + static_cast<std::size_t>(position)]) /
                                density_steps_ * value_range_;
    }
    int density_positions_per_record() const {
        return static_cast<int>(memory_.density_positions * memory_.density_positions * memory_.density_positions);
    }
    // The ranges the records were stored over: what a fixed-point copy of them must cover.
    float value_min() const { return value_min_; }
    float value_max() const { return value_min_ + value_range_; }
    bool integer_values() const { return integer_values_; }
    float largest_gradient() const { return std::max({gradient_max_.x, gradient_max_.y, gradient_max_.z}); }
    // The position a sample snaps to (for the oracle), in the cell's fractions, for density and gradient.
    glm::vec3 snapped_density_fraction(glm::vec3 fraction) const;
    glm::vec3 snapped_gradient_fraction(glm::vec3 fraction) const;
    glm::ivec3 dims() const { return dims_; }

private:
    std::size_t volume_index(int x, int y, int z) const {
        return static_cast<std::size_t>(x) +
               static_cast<std::size_t>(dims_.x) *
                   (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(z));
    }
    int combined(const PositionTable& t, glm::vec3 fraction, std::uint64_t* carried) const;
    // The candidates numbered in storage order (z slice by z slice) into index_ and cell_origin_.
    void number_candidates(const Volume& volume, const std::vector<std::vector<glm::ivec3>>& per_slice,
                           int index_bytes);
    // Each candidate's record: density and gradient interpolated at each quantized position.
    void fill_records(const Volume& volume, const GradientField& gradients);

    glm::ivec3 dims_{0};
    PermMemory memory_;
    PositionTable density_table_{5, 1000, QuantizedPositions::Centers};
    PositionTable gradient_table_{5, 1000, QuantizedPositions::Centers};
    std::vector<std::int32_t> index_;      // per voxel (the cell it is the origin of)
    std::vector<glm::ivec3> cell_origin_;  // per candidate
    // Written whole by fill_records' threads, so allocated without zeroing (a serial pass over memory
    // touched for the first time, before the threads write it again).
    std::unique_ptr<std::uint16_t[]> density_;  // per candidate, D^3 values quantized over the value range
    std::unique_ptr<std::uint8_t[]> gradient_;  // per candidate, G^3 x 3 magnitudes
    std::unique_ptr<std::uint8_t[]> signs_;     // per candidate, G^3 sign bytes
    Sample decode(std::uint32_t candidate, std::size_t density_index, std::size_t gradient_index) const;

    float value_min_ = 0, value_range_ = 1;
    bool integer_values_ = true;
    float density_steps_ = 255;
    glm::vec3 gradient_max_{0.0f};  // per axis, what magnitude 255 means
    std::uint64_t unreduced_ = 0;
};

}  // namespace pp5
