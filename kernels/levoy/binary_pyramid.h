#pragma once
// Levoy's hierarchical spatial enumeration ("Efficient ray tracing of volume data", 1990): a pyramid of
// binary volumes over the cells of the volume. A cell of level 0 is the box between eight neighbouring
// voxels, and it is occupied when any of those eight has non-zero opacity; a cell of level m covers
// 2^m x 2^m x 2^m cells of level 0 and is occupied when any of them is. The top level has one cell.
//
// A sample whose level-0 cell is empty interpolates eight zero opacities, so it is exactly transparent:
// skipping it changes nothing in the image, only the work.

#include "kernels/shared/pp_volume/shaded_codes.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace pp5 {

class BinaryPyramid {
public:
    BinaryPyramid() = default;
    // Built from the voxels' opacities (an opacity code above 0 is non-empty). Every dimension must be >= 2. With
    // `also` (a volume of the same size), a voxel non-empty in either counts.
    static BinaryPyramid from_opacity(const ShadedCodes& volume, const ShadedCodes* also = nullptr);

    int levels() const { return static_cast<int>(levels_.size()); }
    glm::ivec3 cell_dims(int level) const { return levels_[static_cast<std::size_t>(level)].dims; }
    // `cell` must lie inside cell_dims(level).
    bool occupied(int level, glm::ivec3 cell) const {
        const Level& l = levels_[static_cast<std::size_t>(level)];
        return ((l.words[brick_of(cell, l.bricks)] >> in_brick(cell)) & 1u) != 0;
    }
    // For a cell of level 0, how many levels above it, from level 1 up, are empty where it lies: the
    // levels a ray's leap climbs through before it meets an occupied cell (or the top). `cell` must lie
    // inside cell_dims(0), and the volume must have more than one level.
    int empty_levels_above(glm::ivec3 cell) const {
        const glm::ivec3 up = cell >> 1;  // its cell of level 1
        return climb_[brick_of(up, climb_bricks_) * 64 + static_cast<std::size_t>(in_brick(up))];
    }
    std::uint64_t cells(int level) const;
    std::uint64_t occupied_cells(int level) const;
    std::uint64_t total_cells() const;  // over all levels: what building it visits
    // The same for any volume of `voxel_dims` (each >= 2), before one is built.
    static std::uint64_t total_cells_of(glm::ivec3 voxel_dims);
    // True when both mark the same level-0 cells (then every level agrees).
    bool same_cells(const BinaryPyramid& other) const;

private:
    // A level's bits in bricks of 4x4x4 cells, one 64-bit word each: a ray's neighbouring cells share
    // a cache line, so the test made at every sample rarely leaves the processor's caches.
    struct Level {
        glm::ivec3 dims{0};
        glm::ivec3 bricks{0};
        std::vector<std::uint64_t> words;
        std::uint64_t occupied = 0;
    };
    // A cell's brick (row-major over `bricks`, the level's bricks along each axis), and its place in it.
    static std::size_t brick_of(glm::ivec3 cell, glm::ivec3 bricks) {
        const glm::ivec3 b = cell >> 2;
        return static_cast<std::size_t>(b.x) +
               static_cast<std::size_t>(bricks.x) *
                   (static_cast<std::size_t>(b.y) + static_cast<std::size_t>(bricks.y) * static_cast<std::size_t>(b.z));
    }
    static int in_brick(glm::ivec3 cell) { return (cell.x & 3) | ((cell.y & 3) << 2) | ((cell.z & 3) << 4); }
    static Level pack(glm::ivec3 dims, const std::vector<std::uint8_t>& bytes);
    void count_empty_levels();
    std::vector<Level> levels_;
    // Per cell of level 1, in bricks of 4x4x4 cells (64 bytes, one cache line each): the count of empty
    // levels from level 1 up where it lies (empty_levels_above).
    glm::ivec3 climb_bricks_{0};
    std::vector<std::uint8_t> climb_;
};

}  // namespace pp5
