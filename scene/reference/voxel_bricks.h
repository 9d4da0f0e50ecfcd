#pragma once
// The shading inputs of every occupancy block stored together: gradient and value of the block's
// voxels, x fastest within the block, blocks one after another. Shading a block then reads one short
// contiguous run of memory instead of a few dozen scattered rows of two arrays, which is what on-demand
// shading (blocks in the order rays meet them, mostly not in cache) spends its time waiting for.
// Built once per volume; a copy of data the volume and gradient field already hold (16 bytes a voxel).

#include "scene/reference/gradient_field.h"
#include "scene/reference/occupancy_grid.h"
#include "scene/volume/volume.h"

#include <glm/vec4.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace pp5 {

class VoxelBricks {
public:
    VoxelBricks(const Volume& volume, const GradientField& gradients);
    // The same volume's voxels with other gradients (a capping region moved), in the storage they had.
    void refill(const Volume& volume, const GradientField& gradients);

    // (gradient x, y, z, value) of the block's voxels from OccupancyGrid::first_voxel to last_voxel.
    std::span<const glm::vec4> brick(std::size_t block_index) const {
        return {data_.data() + offsets_[block_index], offsets_[block_index + 1] - offsets_[block_index]};
    }
    glm::ivec3 volume_dims() const { return volume_dims_; }
    // The offset of a block's first voxel in brick order (for per-voxel data gathered the same way).
    std::size_t offset(std::size_t block_index) const { return offsets_[block_index]; }
    // A per-voxel array (Volume::index order) rearranged into brick order.
    std::vector<float> gather(std::span<const float> per_voxel) const;

private:
    template <class Visit>
    void for_each_voxel(Visit&& visit) const;  // visit(brick order position, Volume::index), in parallel

    glm::ivec3 volume_dims_;
    std::vector<std::size_t> offsets_;  // block_count + 1
    std::vector<glm::vec4> data_;
};

}  // namespace pp5
