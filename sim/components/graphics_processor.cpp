#include "sim/components/graphics_processor.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <stdexcept>

namespace pp5 {

const ParamGroup& GraphicsProcessor::params() {
    static const ParamGroup group = [] {
        ParamGroup g("gp", "Graphics processors: Intel i860 nodes with memory and a block cache");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.integer("count", 32, "count", 1, 1024, "Number of graphics processors", Provenance::Paper,
                  "Levoy 1989, Implementation on Pixel-planes 5: 32 GPs")
            .real("clock_mhz", 40.0, "MHz", 1, 10000,
                  "i860 core clock (up to 10 GHz for other processors, such as the host preset)", Provenance::Hardware,
                  "Fuchs et al. 1989: Intel i860 at 40 MHz")
            .real("sustained_mflops", 20.0, "MFLOPS", 0.1, 1e5, "Floating-point rate a GP sustains on ray tracing",
                  Provenance::Paper, "Levoy 1989: 20-MFLOP graphics processors (i860 peak is 80)")
            .integer("cache_bits", 16 * 1024 * 1024, "bits", 1024, 1LL << 40,
                     "Block cache capacity per GP (16 Mbit = 2 MiB); it must fit in gp.memory_bytes with the kernel's "
                     "own data",
                     Provenance::Paper, "Levoy 1989: voxels retained in a 16Mb local cache")
            .integer("memory_bytes", 8 * 1024 * 1024, "bytes", 1024, 1LL << 40,
                     "Memory per GP board: holds the block cache and what a kernel keeps on every GP (Levoy's pyramid)",
                     Provenance::Default, "machine.md: about 8 MB per GP board, not confirmed")
            .plausible(4 << 20, 16 << 20, "a board of the time held 4-16 MB; only what fits changes")
            .integer("ray_contexts", 8, "count", 1, 4096,
                     "Items (rays) a GP keeps in flight, switching between them while fetches are outstanding",
                     Provenance::Default, "Levoy 1989 says 'several rays' without a number")
            .plausible(2, 16,
                       "'several' is more than one; the i860's 32 registers and a context's state of about 16 "
                       "words make more than 16 unlikely")
            .integer("cache_associativity", 8, "ways", 1, 1 << 20, "Ways per set of the block cache (LRU within a set)",
                     Provenance::Default,
                     "not published: the cache is software on the i860, any organisation is possible")
            .plausible(1, 16,
                       "a software cache could be direct-mapped (cheapest look-up) or search up to a few dozen tags");
        return g;
    }();
    return group;
}

GraphicsProcessor::GraphicsProcessor(std::size_t index, const MachineConfig& config)
    : Component(indexed("gp", index), nullptr),
      tasks(stats().counter("tasks", "count", "Tasks (a tile of rays in one refinement pass, say) finished")),
      items(stats().counter("items", "count", "Items (rays, primitive batches) run to completion")),
      fetch_requests(stats().counter("fetch_requests", "count", "Fetch request messages sent to renderers")),
      blocks_refreshed(
          stats().counter("blocks_refreshed", "count",
                          "Blocks asked for again, a few to a refresh message, after the data they copy changed")),
      replies(stats().counter("replies", "count", "Fetch replies received")),
      context_switches(stats().counter("context_switches", "count", "Switches from a waiting item to a ready one")),
      busy_ps(stats().counter("busy_time", "ps", "Simulated time spent computing")),
      wait_ps(stats().counter("wait_time", "ps",
                              "Simulated time with work left but nothing to run: every item waiting for a block, or "
                              "the next group of tasks not yet open")),
      index_(index),
      clock_(ClockDomain::from_megahertz(name() + ".clock", config.real("gp.clock_mhz"))),
      cache_bits_(static_cast<std::uint64_t>(config.integer("gp.cache_bits"))),
      memory_bytes_(static_cast<std::uint64_t>(config.integer("gp.memory_bytes"))),
      ray_contexts_(static_cast<int>(config.integer("gp.ray_contexts"))),
      cache_associativity_(static_cast<int>(config.integer("gp.cache_associativity"))),
      costs_(GpCostModel::from(config)) {}

BlockCache& GraphicsProcessor::cache(std::uint64_t block_bits) {
    if (block_bits == 0) throw std::invalid_argument("cache blocks need at least one bit");
    if (cache_ && block_bits != cache_block_bits_)
        throw std::logic_error(name() + ": cache already built for another block size");
    if (!cache_) {
        const std::uint64_t blocks = cache_bits_ / block_bits;
        if (blocks == 0) {
            reject_field("gp.cache_bits", "the block cache (" + std::to_string(cache_bits_) +
                                              " bits) cannot hold one block of " + std::to_string(block_bits) +
                                              " bits");
        }
        if (cache_bits_ / 8 > memory_bytes_)
            reject_field("gp.cache_bits",
                         fmt::format("a {} byte cache does not fit in the GP's {} bytes of memory (gp.memory_bytes)",
                                     cache_bits_ / 8, memory_bytes_));
        // The simulator keeps a tag and use counts per block: refuse caches this computer cannot hold.
        const std::uint64_t host_bytes_per_block = BlockCache::host_bytes_per_block();
        constexpr std::uint64_t kMostHostBytes = std::uint64_t{1} << 30;
        if (blocks > kMostHostBytes / host_bytes_per_block)
            reject_field(
                "gp.cache_bits",
                fmt::format(
                    "{} blocks a GP would take {} MiB of this computer's memory to simulate, per GP; at most {} MiB",
                    blocks, blocks * host_bytes_per_block >> 20, kMostHostBytes >> 20));
        cache_block_bits_ = block_bits;
        cache_ = std::make_unique<BlockCache>(this, blocks, cache_associativity_);
    }
    return *cache_;
}

Counter& GraphicsProcessor::operations(const std::string& kind) {
    auto it = operations_.find(kind);
    if (it == operations_.end())
        it = operations_
                 .emplace(kind,
                          &stats().counter("operations." + kind, "count", "Operations of the kernel's kind " + kind))
                 .first;
    return *it->second;
}

}  // namespace pp5
