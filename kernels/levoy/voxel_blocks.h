#pragma once
// What one voxel request asks for: a block of b x b x b cells, that is the (b+1)^3 voxels at their
// corners (neighbouring blocks share a face of voxels, so every sample's eight voxels are in one
// block). A block's voxels may lie on several renderers (always with the slices placement, at brick
// faces with bricks): the GP asks each of them for its part and has the block when every part is in.

#include "kernels/shared/pp_volume/voxel_placement.h"
#include "sim/timing/recorded_work.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace pp5 {

class VoxelBlocks {
public:
    // block_cells >= 1; voxel_bits: what a voxel's colour and opacity take on the ring and in the cache.
    VoxelBlocks(const VoxelPlacement& placement, int block_cells, int voxel_bits);

    int block_cells() const { return block_cells_; }
    std::uint64_t block_count() const {
        return static_cast<std::uint64_t>(blocks_.x) * static_cast<std::uint64_t>(blocks_.y) *
               static_cast<std::uint64_t>(blocks_.z);
    }
    // The cache's unit: a whole block's voxels (blocks at the volume's far faces are smaller, but take a
    // whole cache block).
    std::uint64_t block_bits() const;
    int voxel_bits() const { return voxel_bits_; }

    // Called for every sample a GP resamples: three table look-ups instead of three divisions.
    std::uint32_t block_of(glm::ivec3 cell) const {
        return x_part_[static_cast<std::size_t>(cell.x)] + y_part_[static_cast<std::size_t>(cell.y)] +
               z_part_[static_cast<std::size_t>(cell.z)];
    }
    // Every block's parts (the renderers holding its voxels, with how many each, in renderer order),
    // for the timing engine: a unit is one voxel's colour and opacity.
    std::shared_ptr<const BlockDirectory> directory() const;

private:
    const VoxelPlacement& placement_;
    int block_cells_;
    int voxel_bits_;
    glm::ivec3 blocks_;
    std::vector<std::uint32_t> x_part_, y_part_, z_part_;  // a cell coordinate's share of its block number
};

}  // namespace pp5
