#pragma once
// A graphics processor (GP): an Intel i860 with a voxel cache. In Levoy's design each GP owns a set of
// rays, requests shaded voxels from the renderers over the ring, interpolates and composites, and
// switches rays while a request is outstanding. This component holds a GP's parameters, cost model,
// cache and statistics; the ray caster's timing layer (kernels/levoy/ray_cast_timing.h) drives it.

#include "sim/components/gp_cost_model.h"
#include "sim/components/voxel_cache.h"
#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"

#include <memory>

namespace pp5 {

class GraphicsProcessor : public Component {
public:
    static const ParamGroup& params();

    GraphicsProcessor(std::size_t index, const MachineConfig& config);

    std::size_t index() const { return index_; }
    const ClockDomain& clock() const { return clock_; }
    std::uint64_t cache_bits() const { return cache_bits_; }
    int ray_contexts() const { return ray_contexts_; }
    const GpCostModel& costs() const { return costs_; }

    // The voxel cache for blocks of `block_bits` bits: built on first use (its capacity in blocks
    // depends on what the kernel's requests return); later calls must ask for the same block size.
    VoxelCache& cache(std::uint64_t block_bits);
    VoxelCache* cache_if_built() { return cache_.get(); }

    Counter& rays;
    Counter& samples;
    Counter& samples_skipped;
    Counter& pyramid_steps;
    Counter& rays_terminated;
    Counter& pixels_filled;
    Counter& requests;
    Counter& replies;
    Counter& context_switches;
    Counter& busy_ps;
    Counter& wait_ps;

private:
    std::size_t index_;
    ClockDomain clock_;
    std::uint64_t cache_bits_;
    int ray_contexts_;
    int cache_associativity_;
    GpCostModel costs_;
    std::uint64_t cache_block_bits_ = 0;
    std::unique_ptr<VoxelCache> cache_;
};

}  // namespace pp5
