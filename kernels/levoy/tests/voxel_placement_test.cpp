// Voxel placement: every voxel has exactly one home, the homes agree with the slot frames the
// programs run over, and a volume that does not fit is told what it would need.

#include "kernels/shared/pp_volume/voxel_placement.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>

namespace pp5 {
namespace {

const PpArrayShape kPxpl5{16, 128, 128, 4096};

TEST(VoxelPlacement, LevoysVolumeFillsTheMachineExactly) {
    // 256^3 voxels of 8 bytes on 16 renderers of 128x128 PPs with 4K bits each: 64 slots, all used.
    for (PlacementPolicy policy : {PlacementPolicy::Bricks, PlacementPolicy::Slices}) {
        const VoxelPlacement p(policy, glm::ivec3(256), kPxpl5, 64);
        EXPECT_EQ(p.slots_available(), 64);
        EXPECT_EQ(p.slots_needed(), 64) << to_string(policy);
        EXPECT_TRUE(p.fits());
        EXPECT_EQ(p.shortfall(), "");
        EXPECT_EQ(p.backing_store_bits_used(), 4096u);
        for (int r = 0; r < 16; ++r) EXPECT_EQ(p.slots_used(r), 64);
    }
}

TEST(VoxelPlacement, BricksGiveEachRendererASolidBlock) {
    const VoxelPlacement p(PlacementPolicy::Bricks, glm::ivec3(256), kPxpl5, 64);
    // Renderer 0 holds x, y in [0,128) and z in [0,64); renderer 1 the next 64 slices.
    EXPECT_EQ(p.frame(0, 0).origin, glm::ivec3(0, 0, 0));
    EXPECT_EQ(p.frame(0, 63).origin, glm::ivec3(0, 0, 63));
    EXPECT_EQ(p.frame(1, 0).origin, glm::ivec3(0, 0, 64));
    EXPECT_EQ(p.frame(4, 0).origin, glm::ivec3(128, 0, 0));
    const PpLocation home = p.locate(glm::ivec3(130, 5, 70));
    EXPECT_EQ(home.renderer, 5);
    EXPECT_EQ(home.pp, 2 + 5 * 128);
    EXPECT_EQ(home.slot, 6);
}

TEST(VoxelPlacement, SlicesDealNeighbouringSlicesToDifferentRenderers) {
    const VoxelPlacement p(PlacementPolicy::Slices, glm::ivec3(256), kPxpl5, 64);
    for (int z = 0; z < 32; ++z) EXPECT_EQ(p.locate(glm::ivec3(7, 9, z)).renderer, z % 16);
}

// Every voxel of an odd-sized volume is reached by exactly one (renderer, slot, PP), and locate()
// finds the same home.
TEST(VoxelPlacement, EveryVoxelHasOneHomeAtOddSizes) {
    const PpArrayShape small{3, 5, 4, 640};
    const glm::ivec3 dims(11, 9, 7);
    for (PlacementPolicy policy : {PlacementPolicy::Bricks, PlacementPolicy::Slices}) {
        const VoxelPlacement p(policy, dims, small, 10);
        ASSERT_TRUE(p.fits()) << p.shortfall();
        std::set<std::tuple<int, int, int>> seen;
        int visited = 0;
        for (int r = 0; r < small.renderers; ++r) {
            for (int s = 0; s < p.slots_needed(); ++s) {
                const SlotFrame f = p.frame(r, s);
                if (!f.used) continue;
                for (int row = 0; row < small.rows; ++row) {
                    for (int col = 0; col < small.columns; ++col) {
                        const glm::ivec3 v = f.origin + glm::ivec3(col, row, 0);
                        if (v.x >= dims.x || v.y >= dims.y) continue;
                        ++visited;
                        EXPECT_TRUE(seen.insert({v.x, v.y, v.z}).second) << "voxel placed twice";
                        const PpLocation home = p.locate(v);
                        EXPECT_EQ(home.renderer, r);
                        EXPECT_EQ(home.slot, s);
                        EXPECT_EQ(home.pp, col + row * small.columns);
                    }
                }
            }
        }
        EXPECT_EQ(visited, dims.x * dims.y * dims.z) << to_string(policy);
    }
}

TEST(VoxelPlacement, AVolumeThatDoesNotFitSaysWhatItWouldNeed) {
    const VoxelPlacement p(PlacementPolicy::Bricks, glm::ivec3(256, 256, 320), kPxpl5, 64);
    EXPECT_FALSE(p.fits());
    EXPECT_EQ(p.slots_needed(), 80);
    const std::string why = p.shortfall();
    EXPECT_NE(why.find("80 slots of 64 bits (5120 bits)"), std::string::npos) << why;
    EXPECT_NE(why.find("1024 bits short"), std::string::npos) << why;
    EXPECT_NE(why.find("20 renderers"), std::string::npos) << why;
    EXPECT_NE(why.find("at most 51 bits per voxel"), std::string::npos) << why;
}

TEST(VoxelPlacement, PolicyNamesRoundTrip) {
    EXPECT_EQ(parse_placement_policy("bricks"), PlacementPolicy::Bricks);
    EXPECT_EQ(parse_placement_policy("slices"), PlacementPolicy::Slices);
    EXPECT_FALSE(parse_placement_policy("random").has_value());
}

}  // namespace
}  // namespace pp5
