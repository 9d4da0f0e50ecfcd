#include "scene/reference/occupancy_grid.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace pp5 {

namespace {

int blocks_along(int voxels) {
    // Positions span [0, voxels-1]; at least one block even for a single voxel.
    return std::max(1, (voxels - 1 + OccupancyGrid::kBlockSize - 1) / OccupancyGrid::kBlockSize);
}

glm::ivec3 block_of_index(std::size_t index, glm::ivec3 block_dims) {
    const std::size_t nx = static_cast<std::size_t>(block_dims.x);
    const std::size_t ny = static_cast<std::size_t>(block_dims.y);
    return {static_cast<int>(index % nx), static_cast<int>((index / nx) % ny), static_cast<int>(index / (nx * ny))};
}

// Runs decide(layout, block) -> bool for every block in parallel (each writes its own flag) and builds
// the grid from the answers. `layout` is an empty grid of the same shape, for block geometry.
template <class Decide>
OccupancyGrid build_grid(glm::ivec3 dims, Decide&& decide) {
    const OccupancyGrid layout(dims);
    std::vector<std::uint8_t> flags(layout.block_count(), 0);
    const glm::ivec3 blocks = layout.block_dims();
    pp5::parallel_for(tbb::blocked_range<std::size_t>(0, layout.block_count()),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i)
                              flags[i] = decide(layout, block_of_index(i, blocks)) ? 1 : 0;
                      });
    return OccupancyGrid(dims, flags);
}

// One pass of the separable Chebyshev distance transform along an axis: d'(p) = min over q on the
// line through p of max(d(q), |p - q|), looking no further than kMaxDistance.
void chebyshev_pass(std::vector<std::uint8_t>& distance, glm::ivec3 blocks, int axis) {
    const std::size_t stride[3] = {1, static_cast<std::size_t>(blocks.x),
                                   static_cast<std::size_t>(blocks.x) * static_cast<std::size_t>(blocks.y)};
    const int length = blocks[axis];
    const int u_axis = axis == 0 ? 1 : 0;
    const int v_axis = axis == 2 ? 1 : 2;
    const int lines = blocks[u_axis] * blocks[v_axis];
    pp5::parallel_for(tbb::blocked_range<int>(0, lines), [&](const tbb::blocked_range<int>& r) {
        std::vector<std::uint8_t> line(static_cast<std::size_t>(length));
        for (int l = r.begin(); l != r.end(); ++l) {
            const std::size_t start = static_cast<std::size_t>(l % blocks[u_axis]) * stride[u_axis] +
                                      static_cast<std::size_t>(l / blocks[u_axis]) * stride[v_axis];
            for (int i = 0; i < length; ++i)
                line[static_cast<std::size_t>(i)] = distance[start + static_cast<std::size_t>(i) * stride[axis]];
            for (int i = 0; i < length; ++i) {
                int best = line[static_cast<std::size_t>(i)];
                const int reach = std::min(best, OccupancyGrid::kMaxDistance);
                for (int j = std::max(0, i - reach + 1); j < std::min(length, i + reach); ++j) {
                    best =
                        std::min(best, std::max(static_cast<int>(line[static_cast<std::size_t>(j)]), std::abs(i - j)));
                }
                distance[start + static_cast<std::size_t>(i) * stride[axis]] = static_cast<std::uint8_t>(best);
            }
        }
    });
}

// True if any voxel of the block's test range satisfies nonzero(voxel index).
template <class NonZero>
bool any_in_test_range(const OccupancyGrid& grid, glm::ivec3 block, NonZero&& nonzero) {
    const glm::ivec3 dims = grid.volume_dims();
    const glm::ivec3 lo = grid.test_begin(block);
    const glm::ivec3 hi = grid.test_last(block);
    for (int z = lo.z; z <= hi.z; ++z) {
        for (int y = lo.y; y <= hi.y; ++y) {
            const std::size_t row =
                static_cast<std::size_t>(dims.x) *
                (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(z));
            for (int x = lo.x; x <= hi.x; ++x) {
                if (nonzero(row + static_cast<std::size_t>(x))) return true;
            }
        }
    }
    return false;
}

std::size_t voxel_count(glm::ivec3 dims) {
    return static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
}

}  // namespace

glm::ivec3 OccupancyGrid::block_dims_for(glm::ivec3 volume_dims) {
    return {blocks_along(volume_dims.x), blocks_along(volume_dims.y), blocks_along(volume_dims.z)};
}

OccupancyGrid::OccupancyGrid(glm::ivec3 volume_dims, bool occupied)
    : volume_dims_(volume_dims),
      block_dims_(block_dims_for(volume_dims)),
      distance_(static_cast<std::size_t>(block_dims_.x) * static_cast<std::size_t>(block_dims_.y) *
                    static_cast<std::size_t>(block_dims_.z),
                occupied ? std::uint8_t{0} : static_cast<std::uint8_t>(kMaxDistance)) {}

OccupancyGrid::OccupancyGrid(glm::ivec3 volume_dims, const std::vector<std::uint8_t>& occupied_flags)
    : OccupancyGrid(volume_dims) {
    if (occupied_flags.size() != distance_.size()) throw std::invalid_argument("OccupancyGrid: one flag per block");
    for (std::size_t i = 0; i < distance_.size(); ++i) {
        distance_[i] = occupied_flags[i] != 0 ? std::uint8_t{0} : static_cast<std::uint8_t>(kMaxDistance);
    }
    for (int axis = 0; axis < 3; ++axis) chebyshev_pass(distance_, block_dims_, axis);
}

std::size_t OccupancyGrid::occupied_count() const {
    return static_cast<std::size_t>(std::count(distance_.begin(), distance_.end(), std::uint8_t{0}));
}

glm::ivec3 OccupancyGrid::last_voxel(glm::ivec3 block) const {
    // The last block on an axis runs to the last voxel.
    glm::ivec3 last = block * kBlockSize + (kBlockSize - 1);
    for (int a = 0; a < 3; ++a) {
        if (block[a] == block_dims_[a] - 1) last[a] = volume_dims_[a] - 1;
    }
    return glm::min(last, volume_dims_ - 1);
}

glm::ivec3 OccupancyGrid::test_begin(glm::ivec3 block) const { return glm::max(block * kBlockSize - 1, glm::ivec3(0)); }

glm::ivec3 OccupancyGrid::test_last(glm::ivec3 block) const {
    return glm::min(block * kBlockSize + (kBlockSize + 1), volume_dims_ - 1);
}

std::vector<glm::ivec3> OccupancyGrid::occupied_blocks() const {
    std::vector<glm::ivec3> blocks;
    for (std::size_t i = 0; i < distance_.size(); ++i) {
        if (distance_[i] == 0) blocks.push_back(block_of_index(i, block_dims_));
    }
    return blocks;
}

OccupancyGrid occupancy_from_opacity(glm::ivec3 dims, std::span<const float> opacity) {
    if (opacity.size() != voxel_count(dims)) throw std::invalid_argument("occupancy_from_opacity: size mismatch");
    return build_grid(dims, [&](const OccupancyGrid& grid, glm::ivec3 block) {
        return any_in_test_range(grid, block, [&](std::size_t i) { return opacity[i] != 0.0f; });
    });
}

OccupancyGrid occupancy_from_alpha(glm::ivec3 dims, std::span<const glm::vec4> rgba) {
    if (rgba.size() != voxel_count(dims)) throw std::invalid_argument("occupancy_from_alpha: size mismatch");
    return build_grid(dims, [&](const OccupancyGrid& grid, glm::ivec3 block) {
        return any_in_test_range(grid, block, [&](std::size_t i) { return rgba[i].a != 0.0f; });
    });
}

BlockValueRanges compute_block_value_ranges(const Volume& volume, const GradientField& gradients) {
    if (gradients.dims != volume.dims())
        throw std::invalid_argument("compute_block_value_ranges: gradients of another volume");
    const OccupancyGrid layout(volume.dims());
    BlockValueRanges ranges;
    ranges.volume_dims = volume.dims();
    ranges.min_value.resize(layout.block_count());
    ranges.max_value.resize(layout.block_count());
    ranges.max_gradient.resize(layout.block_count());
    const std::span<const float> values = volume.samples();
    pp5::parallel_for(tbb::blocked_range<std::size_t>(0, layout.block_count()),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t b = r.begin(); b != r.end(); ++b) {
                              float lo = std::numeric_limits<float>::infinity();
                              float hi = -lo;
                              float longest = 0.0f;  // squared
                              any_in_test_range(layout, block_of_index(b, layout.block_dims()), [&](std::size_t i) {
                                  lo = std::min(lo, values[i]);
                                  hi = std::max(hi, values[i]);
                                  longest = std::max(longest, glm::dot(gradients.at(i), gradients.at(i)));
                                  return false;  // visit every voxel
                              });
                              ranges.min_value[b] = lo;
                              ranges.max_value[b] = hi;
                              ranges.max_gradient[b] = std::sqrt(longest);
                          }
                      });
    return ranges;
}

OccupancyGrid occupancy_from_value_ranges(const BlockValueRanges& ranges, const Classification& classification) {
    return build_grid(ranges.volume_dims, [&](const OccupancyGrid& grid, glm::ivec3 block) {
        const std::size_t b = grid.block_index(block);
        // Trilinear weights are rounded, so a sample can leave its corners' range by a few ulps.
        const float lo = ranges.min_value[b];
        const float hi = ranges.max_value[b];
        const float slack = 1e-5f * std::max({std::abs(lo), std::abs(hi), 1.0f});
        // A block whose gradients are all zero interpolates to exactly zero; keep that exact.
        const float steepest = ranges.max_gradient[b];
        const float longest = steepest > 0.0f ? steepest * (1.0f + 1e-5f) + 1e-6f : 0.0f;
        return classification.may_be_nonzero(lo - slack, hi + slack, longest);
    });
}

}  // namespace pp5
