#pragma once
// Voxel shading on demand: a block of voxels is shaded the first time a sample needs one of its
// voxels, during compositing. With early termination a ray reads only the first surfaces it meets, so
// in an animation most occupied blocks are never needed in a frame (on the MR head ch2 with a 20->60
// opacity ramp, 0.52 M of the 4.5 M voxels in occupied blocks are shaded per frame). The colours are the ones
// shade_voxels computes, so the image is bit-identical to shading everything first; which thread shades a block does
// not matter.
//
// Each block has a state: to shade, being shaded, ready. The first sample to need a block claims it
// (compare-and-swap) and shades it; another sample needing it meanwhile waits for it (a few
// microseconds). Blocks that are not occupied are ready from the start: their voxels' colours never
// reach the image (occupancy_grid.h), and their opacities are zero.

#include "scene/reference/occupancy_grid.h"
#include "scene/reference/shaded_volume.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <memory>

namespace pp5 {

class OnDemandShading {
public:
    // `shaded` must hold zero opacity outside the occupied blocks of `occupancy`; every occupied block
    // starts unshaded.
    OnDemandShading(ShadedVolume& shaded, const OccupancyGrid& occupancy);

    // Every occupied block is to be shaded again (a new view or lighting).
    void invalidate();
    // Voxels shaded since the last call.
    std::uint64_t take_voxels_shaded() { return voxels_shaded_.exchange(0); }
    // Thread-seconds spent shading since the last call (host time: not deterministic).
    double take_shading_seconds() { return 1e-9 * static_cast<double>(shading_nanoseconds_.exchange(0)); }

    // Makes the eight voxels of the cell with this lower corner readable in the shaded volume.
    void ensure_cell(glm::ivec3 corner, const BlockShader& shader) {
        const glm::ivec3 lo = block_of(corner);
        const glm::ivec3 hi = block_of(corner + 1);
        if (lo == hi) {  // most cells: all eight corners in one block
            ensure_block(lo, shader);
            return;
        }
        for (int z = lo.z; z <= hi.z; ++z) {
            for (int y = lo.y; y <= hi.y; ++y) {
                for (int x = lo.x; x <= hi.x; ++x) ensure_block({x, y, z}, shader);
            }
        }
    }

private:
    enum State : std::uint8_t { kToShade = 0, kShading = 1, kReady = 2 };

    glm::ivec3 block_of(glm::ivec3 voxel) const {  // voxel >= 0
        return glm::min(voxel / OccupancyGrid::kBlockSize, last_block_);
    }
    void ensure_block(glm::ivec3 block, const BlockShader& shader) {
        if (states_[occupancy_.block_index(block)].load(std::memory_order_acquire) != kReady)
            shade_or_wait(block, shader);
    }
    void shade_or_wait(glm::ivec3 block, const BlockShader& shader);

    ShadedVolume& shaded_;
    const OccupancyGrid& occupancy_;
    glm::ivec3 last_block_;
    std::unique_ptr<std::atomic<std::uint8_t>[]> states_;
    std::atomic<std::uint64_t> voxels_shaded_{0};
    std::atomic<std::uint64_t> shading_nanoseconds_{0};
};

}  // namespace pp5
