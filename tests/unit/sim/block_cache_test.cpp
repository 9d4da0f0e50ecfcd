#include "sim/components/block_cache.h"
#include "sim/components/graphics_processor.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <gtest/gtest.h>

namespace pp5 {
namespace {

struct Owner : Component {
    Owner() : Component("gp[0]", nullptr) {}
};

TEST(BlockCache, MissThenHitAfterFill) {
    Owner owner;
    BlockCache cache(&owner, 16, 4);
    EXPECT_FALSE(cache.lookup(7));
    cache.insert(7);
    EXPECT_TRUE(cache.lookup(7));
    EXPECT_EQ(cache.hits.value(), 1u);
    EXPECT_EQ(cache.misses.value(), 1u);
    EXPECT_EQ(cache.fills.value(), 1u);
    EXPECT_EQ(cache.occupancy(), 1u);
}

TEST(BlockCache, FullyAssociativeEvictsTheLeastRecentlyUsed) {
    Owner owner;
    BlockCache cache(&owner, 4, 64);  // associativity above capacity: one set of four
    EXPECT_EQ(cache.associativity(), 4);
    for (std::uint64_t b = 0; b < 4; ++b) cache.insert(b);
    EXPECT_TRUE(cache.lookup(0));  // 1 is now the least recently used
    cache.insert(4);
    EXPECT_FALSE(cache.contains(1));
    for (std::uint64_t b : {0u, 2u, 3u, 4u}) EXPECT_TRUE(cache.contains(b)) << b;
    EXPECT_EQ(cache.evictions.value(), 1u);
    EXPECT_EQ(cache.occupancy(), 4u);
}

TEST(BlockCache, NeverHoldsMoreThanItsCapacity) {
    Owner owner;
    BlockCache cache(&owner, 64, 8);
    for (std::uint64_t b = 0; b < 1000; ++b) cache.insert(b * 37);
    EXPECT_EQ(cache.occupancy(), 64u);
    std::uint64_t held = 0;
    for (std::uint64_t b = 0; b < 1000; ++b) held += cache.contains(b * 37) ? 1 : 0;
    EXPECT_EQ(held, 64u);
    EXPECT_EQ(cache.evictions.value(), 1000u - 64u);
}

TEST(BlockCache, RepeatedFillOfAHeldBlockDoesNotEvict) {
    Owner owner;
    BlockCache cache(&owner, 2, 2);
    cache.insert(1);
    cache.insert(2);
    cache.insert(1);
    EXPECT_TRUE(cache.contains(1));
    EXPECT_TRUE(cache.contains(2));
    EXPECT_EQ(cache.evictions.value(), 0u);
}

TEST(BlockCache, InvalidateDropsEveryBlock) {
    Owner owner;
    BlockCache cache(&owner, 32, 4);
    for (std::uint64_t b = 0; b < 10; ++b) cache.insert(b);
    cache.invalidate();
    EXPECT_EQ(cache.occupancy(), 0u);
    for (std::uint64_t b = 0; b < 10; ++b) EXPECT_FALSE(cache.contains(b));
    EXPECT_EQ(cache.invalidations.value(), 1u);
}

TEST(BlockCache, BlocksUsedThisFrameComeInTheOrderOfTheirFirstUse) {
    Owner owner;
    BlockCache cache(&owner, 16, 16);
    cache.insert(3);
    cache.insert(9);
    cache.begin_frame();  // a new frame: nothing used in it yet
    EXPECT_TRUE(cache.blocks_used_this_frame().empty());
    EXPECT_TRUE(cache.lookup(9));  // first use: 9
    cache.insert(5);               // a fill after a miss is a use: 5
    EXPECT_TRUE(cache.lookup(3));  // then 3
    EXPECT_TRUE(cache.lookup(9));  // used again: still first
    cache.insert(11, false);       // a refreshed copy nobody asked for yet is not a use
    EXPECT_EQ(cache.blocks_used_this_frame(), (std::vector<std::uint64_t>{9, 5, 3}));
    EXPECT_TRUE(cache.lookup(11));  // until a ray looks it up
    EXPECT_EQ(cache.blocks_used_this_frame(), (std::vector<std::uint64_t>{9, 5, 3, 11}));
    cache.begin_frame();
    EXPECT_TRUE(cache.blocks_used_this_frame().empty());
}

TEST(BlockCache, GpCacheCapacityIsCacheBitsOverBlockBits) {
    MachineConfig config = Machine::default_config();
    config.apply_override("gp.cache_associativity=4");
    GraphicsProcessor gp(0, config);
    // 16 Mbit over blocks of 5^3 voxels of 32 bits: 4194 blocks, rounded down to whole sets of 4.
    BlockCache& cache = gp.cache(125 * 32);
    EXPECT_EQ(cache.capacity_blocks(), (16u * 1024 * 1024 / 4000) / 4 * 4);
    EXPECT_EQ(&gp.cache(125 * 32), &cache);
    EXPECT_THROW(gp.cache(64), std::logic_error);
}

TEST(BlockCache, CacheTooSmallForOneBlockNamesTheParameter) {
    MachineConfig config = Machine::default_config();
    config.apply_override("gp.cache_bits=1024");
    GraphicsProcessor gp(0, config);
    try {
        gp.cache(4000);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "gp.cache_bits");
    }
}

}  // namespace
}  // namespace pp5
