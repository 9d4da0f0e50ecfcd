#pragma once
// A graphics processor (GP): an Intel i860 with its memory and a block cache. In Levoy's design each GP
// owns a set of rays, fetches shaded voxels from the renderers over the ring, interpolates and
// composites, and switches rays while a fetch is outstanding; other kernels give GPs other work. This
// component holds a GP's parameters, its machine-level cost model, its cache and its statistics; the
// timing engine (sim/timing/frame_engine.h) drives it with a kernel's recorded work.

#include "sim/components/block_cache.h"
#include "sim/components/gp_cost_model.h"
#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"

#include <map>
#include <memory>
#include <string>

namespace pp5 {

class GraphicsProcessor : public Component {
public:
    static const ParamGroup& params();

    GraphicsProcessor(std::size_t index, const MachineConfig& config);

    std::size_t index() const { return index_; }
    const ClockDomain& clock() const { return clock_; }
    std::uint64_t cache_bits() const { return cache_bits_; }
    std::uint64_t memory_bytes() const { return memory_bytes_; }
    int ray_contexts() const { return ray_contexts_; }
    const GpCostModel& costs() const { return costs_; }

    // The block cache for blocks of `block_bits` bits: built on first use (its capacity in blocks
    // depends on what the kernel's fetches return); later calls must ask for the same block size.
    BlockCache& cache(std::uint64_t block_bits);
    BlockCache* cache_if_built() { return cache_.get(); }

    // How many operations of a kernel's kind ("levoy.sample") this GP has done: a counter made on first
    // use, so a GP's statistics list the kinds its kernels really ran.
    Counter& operations(const std::string& kind);

    Counter& tasks;
    Counter& items;
    Counter& fetch_requests;
    Counter& blocks_refreshed;
    Counter& replies;
    Counter& context_switches;
    Counter& busy_ps;
    Counter& wait_ps;

private:
    std::size_t index_;
    ClockDomain clock_;
    std::uint64_t cache_bits_;
    std::uint64_t memory_bytes_;
    int ray_contexts_;
    int cache_associativity_;
    GpCostModel costs_;
    std::uint64_t cache_block_bits_ = 0;
    std::unique_ptr<BlockCache> cache_;
    std::map<std::string, Counter*> operations_;
};

}  // namespace pp5
