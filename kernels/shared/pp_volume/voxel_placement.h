#pragma once
// Where each voxel lives on the machine: which renderer, which pixel processor (PP) and which slot of
// that PP's backing store. Levoy gives each PP a column of voxels, one per slot (64 slots of 8 bytes
// for a 256^3 volume on 16 renderers of 128x128 PPs). Two policies:
//
//  bricks  the volume is cut into tiles of columns x rows voxels in x and y; each (tile, z) slice of a
//          tile is a "unit", and units are dealt to renderers in runs, so each renderer holds a solid
//          brick (128x128x64 of a 256^3 volume). Neighbouring voxels are mostly on one renderer.
//  slices  z-slices are dealt round-robin to the renderers (slice z on renderer z mod N), then tiled
//          as for bricks: neighbouring slices are on different renderers, so a ray's voxel requests
//          spread over all of them (the placement Neumann and Yoo et al. used for Pixel-planes 5).
//
// In both, within one (renderer, slot) the voxel at PP column c, row r is origin + (c, r, 0): an
// affine map, which is what lets the QEE give every PP a linear function of its voxel's position.

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace pp5 {

enum class PlacementPolicy { Bricks, Slices };

std::string to_string(PlacementPolicy policy);
std::optional<PlacementPolicy> parse_placement_policy(const std::string& name);

struct PpArrayShape {
    int renderers = 16;
    int columns = 128;
    int rows = 128;
    int backing_store_bits = 4096;
};

// The voxels one slot of one renderer holds: voxel (origin.x + column, origin.y + row, origin.z) for
// the PPs where that lies inside the volume.
struct SlotFrame {
    glm::ivec3 origin{0};
    bool used = false;  // false: no voxel of the volume is in this slot
};

struct PpLocation {
    int renderer = 0;
    int pp = 0;  // column + row * columns
    int slot = 0;
};

class VoxelPlacement {
public:
    // record_bits: backing-store bits per voxel. Does not throw when the volume does not fit: fits()
    // and shortfall() say so, and the caller decides.
    VoxelPlacement(PlacementPolicy policy, glm::ivec3 volume_dims, PpArrayShape shape, int record_bits);

    PlacementPolicy policy() const { return policy_; }
    glm::ivec3 volume_dims() const { return dims_; }
    const PpArrayShape& shape() const { return shape_; }
    int record_bits() const { return record_bits_; }
    int slots_available() const { return shape_.backing_store_bits / record_bits_; }
    int slots_needed() const { return slots_needed_; }  // per PP, on the busiest renderer
    bool fits() const { return slots_needed_ <= slots_available(); }
    std::uint64_t backing_store_bits_used() const {
        return static_cast<std::uint64_t>(slots_needed_) * static_cast<std::uint64_t>(record_bits_);
    }

    // Empty when the volume fits; otherwise what the machine would need instead: more backing store
    // per PP, more renderers, or fewer bits per voxel (each on its own).
    std::string shortfall() const;

    SlotFrame frame(int renderer, int slot) const;
    int slots_used(int renderer) const;  // slots of `renderer` holding voxels
    PpLocation locate(glm::ivec3 voxel) const;

private:
    std::int64_t unit_of(int renderer, int slot) const;

    PlacementPolicy policy_;
    glm::ivec3 dims_;
    PpArrayShape shape_;
    int record_bits_;
    int tiles_x_;
    int tiles_y_;
    std::int64_t units_;       // tile slices in all
    int slices_per_renderer_;  // Slices: ceil(dims.z / renderers)
    int slots_needed_;
};

}  // namespace pp5
