#include "kernels/shared/pp_volume/voxel_placement.h"

#include <fmt/format.h>

#include <stdexcept>

namespace pp5 {

namespace {

std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

}  // namespace

std::string to_string(PlacementPolicy policy) { return policy == PlacementPolicy::Bricks ? "bricks" : "slices"; }

std::optional<PlacementPolicy> parse_placement_policy(const std::string& name) {
    if (name == "bricks") return PlacementPolicy::Bricks;
    if (name == "slices") return PlacementPolicy::Slices;
    return std::nullopt;
}

VoxelPlacement::VoxelPlacement(PlacementPolicy policy, glm::ivec3 volume_dims, PpArrayShape shape, int record_bits)
    : policy_(policy), dims_(volume_dims), shape_(shape), record_bits_(record_bits) {
    if (dims_.x < 1 || dims_.y < 1 || dims_.z < 1) throw std::invalid_argument("VoxelPlacement: empty volume");
    if (shape_.renderers < 1 || shape_.columns < 1 || shape_.rows < 1 || shape_.backing_store_bits < 0) {
        throw std::invalid_argument("VoxelPlacement: empty PP array");
    }
    if (record_bits_ < 1) throw std::invalid_argument("VoxelPlacement: record_bits must be positive");
    tiles_x_ = static_cast<int>(ceil_div(dims_.x, shape_.columns));
    tiles_y_ = static_cast<int>(ceil_div(dims_.y, shape_.rows));
    const std::int64_t tiles = static_cast<std::int64_t>(tiles_x_) * tiles_y_;
    units_ = tiles * dims_.z;
    slices_per_renderer_ = static_cast<int>(ceil_div(dims_.z, shape_.renderers));
    slots_needed_ = static_cast<int>(policy_ == PlacementPolicy::Bricks ? ceil_div(units_, shape_.renderers)
                                                                        : tiles * slices_per_renderer_);
}

std::string VoxelPlacement::shortfall() const {
    if (fits()) return {};
    const std::int64_t needed_bits = static_cast<std::int64_t>(slots_needed_) * record_bits_;
    const std::int64_t tiles = static_cast<std::int64_t>(tiles_x_) * tiles_y_;
    const int available = slots_available();
    std::string renderers;
    if (policy_ == PlacementPolicy::Bricks && available > 0) {
        renderers = fmt::format("{} renderers (renderer.count)", ceil_div(units_, available));
    } else if (policy_ == PlacementPolicy::Slices && available >= tiles) {
        renderers = fmt::format("{} renderers (renderer.count)", ceil_div(dims_.z, available / tiles));
    } else {
        renderers = "larger PP arrays (renderer.pp_columns, renderer.pp_rows)";
    }
    return fmt::format(
        "a {}x{}x{} volume placed as {} needs {} slots of {} bits ({} bits) in each PP's backing store, which "
        "has {} ({} bits short); it would fit with {} bits of backing store per PP (renderer.backing_store_bits), "
        "or {}, or at most {} bits per voxel",
        dims_.x, dims_.y, dims_.z, to_string(policy_), slots_needed_, record_bits_, needed_bits,
        shape_.backing_store_bits, needed_bits - shape_.backing_store_bits, needed_bits, renderers,
        shape_.backing_store_bits / slots_needed_);
}

std::int64_t VoxelPlacement::unit_of(int renderer, int slot) const {
    // Bricks: units dealt in runs of slots_needed_; the unit is a tile slice index.
    return static_cast<std::int64_t>(renderer) * slots_needed_ + slot;
}

SlotFrame VoxelPlacement::frame(int renderer, int slot) const {
    if (renderer < 0 || renderer >= shape_.renderers || slot < 0 || slot >= slots_needed_) return {};
    std::int64_t tile = 0;
    int z = 0;
    if (policy_ == PlacementPolicy::Bricks) {
        const std::int64_t unit = unit_of(renderer, slot);
        if (unit >= units_) return {};
        z = static_cast<int>(unit % dims_.z);
        tile = unit / dims_.z;
    } else {
        z = (slot % slices_per_renderer_) * shape_.renderers + renderer;
        tile = slot / slices_per_renderer_;
        if (z >= dims_.z) return {};
    }
    const int tx = static_cast<int>(tile % tiles_x_);
    const int ty = static_cast<int>(tile / tiles_x_);
    return {glm::ivec3(tx * shape_.columns, ty * shape_.rows, z), true};
}

int VoxelPlacement::slots_used(int renderer) const {
    int used = 0;
    for (int s = 0; s < slots_needed_; ++s) used += frame(renderer, s).used ? 1 : 0;
    return used;
}

PpLocation VoxelPlacement::locate(glm::ivec3 v) const {
    if (v.x < 0 || v.y < 0 || v.z < 0 || v.x >= dims_.x || v.y >= dims_.y || v.z >= dims_.z) {
        throw std::out_of_range("VoxelPlacement::locate: voxel outside the volume");
    }
    const int tx = v.x / shape_.columns;
    const int ty = v.y / shape_.rows;
    const std::int64_t tile = tx + static_cast<std::int64_t>(tiles_x_) * ty;
    const int pp = (v.x % shape_.columns) + (v.y % shape_.rows) * shape_.columns;
    if (policy_ == PlacementPolicy::Bricks) {
        const std::int64_t unit = v.z + dims_.z * tile;
        return {static_cast<int>(unit / slots_needed_), pp, static_cast<int>(unit % slots_needed_)};
    }
    const int slot = static_cast<int>(v.z / shape_.renderers + slices_per_renderer_ * tile);
    return {v.z % shape_.renderers, pp, slot};
}

}  // namespace pp5
