#include "scene/reference/occupancy_grid.h"
#include "test_scenes.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace pp5 {
namespace {

constexpr int kB = OccupancyGrid::kBlockSize;

TEST(OccupancyGrid, BlocksCoverPositionsUpToTheLastVoxel) {
    // Positions 0 .. 2B along x: two blocks, the second taking the last voxel on its face.
    const OccupancyGrid grid(glm::ivec3(2 * kB + 1, kB + 3, 1));
    EXPECT_EQ(grid.block_dims(), glm::ivec3(2, 2, 1));
    EXPECT_EQ(grid.last_voxel({1, 1, 0}), glm::ivec3(2 * kB, kB + 2, 0));
    EXPECT_EQ(grid.first_voxel({1, 1, 0}), glm::ivec3(kB, kB, 0));
    EXPECT_EQ(grid.test_begin({1, 0, 0}), glm::ivec3(kB - 1, 0, 0));
    EXPECT_EQ(grid.test_last({0, 0, 0}), glm::ivec3(kB + 1, kB + 1, 0));
}

TEST(OccupancyGrid, ABlockIsOccupiedWhenAnyVoxelNearItIsNotTransparent) {
    const glm::ivec3 dims(5 * kB + 1);
    std::vector<float> opacity(static_cast<std::size_t>(dims.x * dims.y * dims.z), 0.0f);
    const glm::ivec3 voxel(2 * kB, 2 * kB + 1, 2 * kB + 2);  // in block (2, 2, 2)
    opacity[static_cast<std::size_t>(voxel.x + dims.x * (voxel.y + dims.y * voxel.z))] = 0.01f;
    const OccupancyGrid grid = occupancy_from_opacity(dims, opacity);
    // Block 2 owns the voxel. On x it is one voxel above block 1's range and on y two: both inside
    // block 1's test range. On z it is three above: outside.
    EXPECT_TRUE(grid.occupied({2, 2, 2}));
    EXPECT_TRUE(grid.occupied({1, 2, 2}));
    EXPECT_TRUE(grid.occupied({2, 1, 2}));
    EXPECT_TRUE(grid.occupied({1, 1, 2}));
    EXPECT_FALSE(grid.occupied({2, 2, 1}));
    EXPECT_FALSE(grid.occupied({3, 2, 2}));
    EXPECT_EQ(grid.occupied_count(), 4u);
    // Distances are Chebyshev distances in blocks to the nearest occupied block.
    EXPECT_EQ(grid.distance({2, 2, 2}), 0);
    EXPECT_EQ(grid.distance({3, 2, 2}), 1);
    EXPECT_EQ(grid.distance({4, 4, 4}), 2);
    EXPECT_EQ(grid.distance({4, 0, 0}), 2);
    EXPECT_EQ(grid.distance({0, 0, 4}), 2);
}

TEST(OccupancyGrid, DistancesMatchBruteForce) {
    const Volume lumpy = test::lumpy_volume({70, 45, 90});
    std::vector<float> opacity(lumpy.samples().begin(), lumpy.samples().end());
    for (float& a : opacity) a = a > 100.0f ? 1.0f : 0.0f;
    const OccupancyGrid grid = occupancy_from_opacity(lumpy.dims(), opacity);
    const std::vector<glm::ivec3> occupied = grid.occupied_blocks();
    ASSERT_FALSE(occupied.empty());
    const glm::ivec3 blocks = grid.block_dims();
    for (int z = 0; z < blocks.z; ++z) {
        for (int y = 0; y < blocks.y; ++y) {
            for (int x = 0; x < blocks.x; ++x) {
                int nearest = OccupancyGrid::kMaxDistance;
                for (const glm::ivec3& o : occupied) {
                    nearest = std::min(nearest, std::max({std::abs(o.x - x), std::abs(o.y - y), std::abs(o.z - z)}));
                }
                ASSERT_EQ(grid.distance({x, y, z}), nearest) << x << "," << y << "," << z;
            }
        }
    }
}

TEST(OccupancyGrid, EmptyAndFullGrids) {
    const OccupancyGrid empty(glm::ivec3(30, 20, 10));
    EXPECT_EQ(empty.occupied_count(), 0u);
    EXPECT_EQ(empty.distance({0, 0, 0}), OccupancyGrid::kMaxDistance);
    const OccupancyGrid full(glm::ivec3(30, 20, 10), true);
    EXPECT_EQ(full.occupied_count(), full.block_count());
}

}  // namespace
}  // namespace pp5
