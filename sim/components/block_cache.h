#pragma once
// A GP's block cache: what a GP keeps of the blocks it has fetched from the renderers (voxels, for
// Levoy's ray caster), so that the next item, the next group of tasks or the next frame need not ask
// again.
//
// It holds whole blocks (a block is what one fetch returns), set-associative with least recently used
// replacement. Sets are chosen by a multiplicative hash of the block number, so blocks with
// neighbouring numbers spread over the sets. Contents survive between frames and groups;
// invalidate() drops them when the data they copy changes.

#include "sim/core/component.h"

#include <cstdint>
#include <vector>

namespace pp5 {

class BlockCache : public Component {
public:
    // capacity_blocks >= 1; an associativity above the capacity makes the cache fully associative.
    BlockCache(Component* owner, std::uint64_t capacity_blocks, int associativity);

    // Whether `block` is held; a hit makes it the most recently used of its set.
    bool lookup(std::uint64_t block);
    // Whether `block` is held, without touching the replacement order or the counters.
    bool contains(std::uint64_t block) const;
    // Stores `block` (a fill after a miss), evicting its set's least recently used block if full.
    // `used` false: a copy nobody has asked for yet (a refresh), not a use this frame until looked up.
    void insert(std::uint64_t block, bool used = true);
    // Drops every block: the voxels they hold are stale.
    void invalidate();
    // Starts a frame: blocks_used_this_frame() is measured from here.
    void begin_frame() { frame_began_at_ = use_clock_; }
    // The blocks used (hit, or filled after a miss) since begin_frame(), in the order of their first use.
    std::vector<std::uint64_t> blocks_used_this_frame() const;

    std::uint64_t capacity_blocks() const { return sets_ * static_cast<std::uint64_t>(ways_); }
    int associativity() const { return ways_; }
    std::uint64_t occupancy() const { return occupied_; }
    // What the simulation keeps of each block the cache can hold, in this computer's memory.
    static std::uint64_t host_bytes_per_block();

    Counter& hits;
    Counter& misses;
    Counter& fills;
    Counter& evictions;
    Counter& invalidations;

private:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
    std::uint64_t set_of(std::uint64_t block) const;

    std::uint64_t sets_;
    int ways_;
    // A way's tag beside its use counter (the smallest is the LRU), so a look-up touches one place.
    struct Way {
        std::uint64_t tag = kEmpty;
        std::uint64_t last_use = 0;
        std::uint64_t first_use = 0;  // in the current frame (<= frame_began_at_: not used in it)
    };
    void note_use(Way& way) {
        way.last_use = ++use_clock_;
        if (way.first_use <= frame_began_at_) way.first_use = way.last_use;
    }
    std::vector<Way> ways_of_sets_;  // sets_ x ways_
    std::uint64_t use_clock_ = 0;
    std::uint64_t frame_began_at_ = 0;
    std::uint64_t occupied_ = 0;
};

}  // namespace pp5
