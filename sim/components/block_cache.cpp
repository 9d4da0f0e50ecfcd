#include "sim/components/block_cache.h"

#include <algorithm>
#include <stdexcept>

namespace pp5 {

BlockCache::BlockCache(Component* owner, std::uint64_t capacity_blocks, int associativity)
    : Component("cache", owner),
      hits(stats().counter("hits", "count", "Block look-ups that found the block")),
      misses(stats().counter("misses", "count",
                             "Block look-ups that did not (each leads to a request unless one is outstanding)")),
      fills(stats().counter("fills", "count", "Blocks stored after arriving")),
      evictions(stats().counter("evictions", "count", "Blocks dropped to make room")),
      invalidations(stats().counter("invalidations", "count",
                                    "Times every block was dropped because the data they copy changed")) {
    if (capacity_blocks == 0 || associativity < 1)
        throw std::invalid_argument("block cache needs at least one block and one way");
    ways_ = static_cast<int>(std::min<std::uint64_t>(static_cast<std::uint64_t>(associativity), capacity_blocks));
    sets_ = capacity_blocks / static_cast<std::uint64_t>(ways_);
    ways_of_sets_.assign(sets_ * static_cast<std::uint64_t>(ways_), Way{});
    stats().formula("capacity", "blocks", "Blocks the cache holds",
                    [this] { return static_cast<double>(this->capacity_blocks()); });
    stats().formula("hit_rate", "fraction", "hits / (hits + misses)", [this] {
        const auto all = hits.value() + misses.value();
        return all == 0 ? 0.0 : static_cast<double>(hits.value()) / static_cast<double>(all);
    });
}

std::uint64_t BlockCache::host_bytes_per_block() { return sizeof(Way); }

std::uint64_t BlockCache::set_of(std::uint64_t block) const {
    // Fibonacci hashing: the high bits of the product mix every bit of the block number.
    return ((block * 0x9E3779B97F4A7C15ull) >> 20) % sets_;
}

bool BlockCache::contains(std::uint64_t block) const {
    const std::uint64_t base = set_of(block) * static_cast<std::uint64_t>(ways_);
    for (int w = 0; w < ways_; ++w)
        if (ways_of_sets_[base + static_cast<std::uint64_t>(w)].tag == block) return true;
    return false;
}

bool BlockCache::lookup(std::uint64_t block) {
    const std::uint64_t base = set_of(block) * static_cast<std::uint64_t>(ways_);
    for (int w = 0; w < ways_; ++w) {
        const std::uint64_t slot = base + static_cast<std::uint64_t>(w);
        if (ways_of_sets_[slot].tag == block) {
            note_use(ways_of_sets_[slot]);
            ++hits;
            return true;
        }
    }
    ++misses;
    return false;
}

void BlockCache::insert(std::uint64_t block, bool used) {
    if (block == kEmpty) throw std::invalid_argument("block cache: reserved block number");
    const std::uint64_t base = set_of(block) * static_cast<std::uint64_t>(ways_);
    std::uint64_t victim = base;
    for (int w = 0; w < ways_; ++w) {
        const std::uint64_t slot = base + static_cast<std::uint64_t>(w);
        if (ways_of_sets_[slot].tag == block) {  // already there (two requests crossed): refresh it
            if (used) note_use(ways_of_sets_[slot]);
            else ways_of_sets_[slot].last_use = ++use_clock_;
            return;
        }
        if (ways_of_sets_[slot].tag == kEmpty) {
            if (ways_of_sets_[victim].tag != kEmpty) victim = slot;
        } else if (ways_of_sets_[victim].tag != kEmpty &&
                   ways_of_sets_[slot].last_use < ways_of_sets_[victim].last_use) {
            victim = slot;
        }
    }
    if (ways_of_sets_[victim].tag == kEmpty) {
        ++occupied_;
    } else {
        ++evictions;
    }
    ways_of_sets_[victim].tag = block;
    ways_of_sets_[victim].last_use = ++use_clock_;
    ways_of_sets_[victim].first_use = used ? ways_of_sets_[victim].last_use : 0;
    ++fills;
}

std::vector<std::uint64_t> BlockCache::blocks_used_this_frame() const {
    std::vector<const Way*> used;
    for (const Way& way : ways_of_sets_)
        if (way.tag != kEmpty && way.first_use > frame_began_at_) used.push_back(&way);
    std::sort(used.begin(), used.end(), [](const Way* a, const Way* b) { return a->first_use < b->first_use; });
    std::vector<std::uint64_t> blocks;
    blocks.reserve(used.size());
    for (const Way* way : used) blocks.push_back(way->tag);
    return blocks;
}

void BlockCache::invalidate() {
    std::fill(ways_of_sets_.begin(), ways_of_sets_.end(), Way{});
    occupied_ = 0;
    ++invalidations;
}

}  // namespace pp5
