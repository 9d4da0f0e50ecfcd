#pragma once
// Empty-space skipping: a coarse grid of B^3-voxel blocks (B = kBlockSize), each marked occupied or
// empty, that a ray walks with a 3D DDA so it can jump over empty blocks (Levoy's pyramid of binary
// volumes, one level). Each empty block also knows its Chebyshev distance, in blocks, to the nearest
// occupied block (capped at kMaxDistance), so a ray in wide empty space leaps a whole empty cube of
// blocks at once instead of stepping block by block.
//
// Exactness is the point: a block is marked empty only if every sample a ray can take inside it is
// exactly transparent, so skipping changes no pixel. A sample at voxel position p uses the voxels
// floor(p) and floor(p)+1 on each axis. Block b covers positions [Bb, Bb+B); the walk may misplace a
// sample across a block face by a rounding error, so a block's test covers voxels Bb-1 .. Bb+B+1 (one
// voxel below, two above: every corner of every cell a sample near the block can touch).
//
// Positions run from 0 to dims-1; the last block on each axis also takes the position dims-1 when it
// falls on a block face.
//
// Block size: 4 voxels measured best on the MR head (ch2): fewer samples in the empty parts of
// occupied blocks, and on-demand shading shades less, while the distance leaps keep the walk short.

#include "scene/reference/gradient_field.h"
#include "scene/render/classification.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pp5 {

class OccupancyGrid {
public:
    static constexpr int kBlockSize = 4;
    static constexpr int kMaxDistance = 16;

    OccupancyGrid() = default;
    // A grid for a volume of these dimensions with every block empty (or occupied).
    explicit OccupancyGrid(glm::ivec3 volume_dims, bool occupied = false);
    // A grid from one flag per block (non-zero = occupied), in block_index order.
    OccupancyGrid(glm::ivec3 volume_dims, const std::vector<std::uint8_t>& occupied_flags);

    static glm::ivec3 block_dims_for(glm::ivec3 volume_dims);

    glm::ivec3 volume_dims() const { return volume_dims_; }
    glm::ivec3 block_dims() const { return block_dims_; }
    std::size_t block_count() const { return distance_.size(); }
    std::size_t occupied_count() const;

    std::size_t block_index(glm::ivec3 block) const {
        return static_cast<std::size_t>(block.x) +
               static_cast<std::size_t>(block_dims_.x) *
                   (static_cast<std::size_t>(block.y) +
                    static_cast<std::size_t>(block_dims_.y) * static_cast<std::size_t>(block.z));
    }
    bool occupied(glm::ivec3 block) const { return distance_[block_index(block)] == 0; }
    // Chebyshev distance in blocks to the nearest occupied block (0 = occupied), at most kMaxDistance:
    // every block closer than this is empty.
    int distance(glm::ivec3 block) const { return distance_[block_index(block)]; }

    // The voxels that belong to a block (each voxel to exactly one): [first, last] inclusive.
    glm::ivec3 first_voxel(glm::ivec3 block) const { return block * kBlockSize; }
    glm::ivec3 last_voxel(glm::ivec3 block) const;
    // The voxels whose values decide whether a block is occupied: the block widened by 1 below and 2
    // above, clipped to the volume.
    glm::ivec3 test_begin(glm::ivec3 block) const;
    glm::ivec3 test_last(glm::ivec3 block) const;

    // distance() of every block, in block_index order: for the ray walk's inner loop.
    const std::uint8_t* distances() const { return distance_.data(); }

    // The occupied blocks, in block index order.
    std::vector<glm::ivec3> occupied_blocks() const;

    bool operator==(const OccupancyGrid&) const = default;

private:
    glm::ivec3 volume_dims_{0};
    glm::ivec3 block_dims_{0};
    std::vector<std::uint8_t> distance_;
};

// Occupied where any voxel in a block's test range has non-zero opacity: exact for resampling
// pre-classified opacities (a trilinear mix of zeros is zero).
OccupancyGrid occupancy_from_opacity(glm::ivec3 dims, std::span<const float> opacity);
// The same from the alpha of shaded voxels.
OccupancyGrid occupancy_from_alpha(glm::ivec3 dims, std::span<const glm::vec4> rgba);

// Per block, over its test range: the value range and the largest gradient magnitude. Trilinear
// interpolation stays inside a cell's value range and cannot lengthen the gradient, so these bound
// every interpolated sample in the block. They depend on the data alone (computed once per volume);
// a classification turns them into an occupancy grid without touching the voxels again.
struct BlockValueRanges {
    glm::ivec3 volume_dims{0};
    std::vector<float> min_value;
    std::vector<float> max_value;
    std::vector<float> max_gradient;  // value units per voxel
};
BlockValueRanges compute_block_value_ranges(const Volume& volume, const GradientField& gradients);

// Occupied where Classification::may_be_nonzero over the block's ranges (slightly widened to cover
// rounding in interpolation): exact for classifying interpolated samples.
OccupancyGrid occupancy_from_value_ranges(const BlockValueRanges& ranges, const Classification& classification);

}  // namespace pp5
