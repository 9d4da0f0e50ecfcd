#pragma once
// A graphics processor (GP): an Intel i860 with a voxel cache. In Levoy's design each GP owns a set of
// rays, requests shaded voxels from the renderers over the ring, interpolates and composites, and
// switches rays while a request is outstanding. Its timing arrives with the ray-caster work; here it
// declares its parameters and statistics.

#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"

namespace pp5 {

class GraphicsProcessor : public Component {
public:
    static const ParamGroup& params();

    GraphicsProcessor(std::size_t index, const MachineConfig& config);

    std::size_t index() const { return index_; }
    const ClockDomain& clock() const { return clock_; }
    std::uint64_t cache_bits() const { return cache_bits_; }
    int ray_contexts() const { return ray_contexts_; }

    Counter& rays;
    Counter& samples;
    Counter& busy_ps;
    Counter& wait_ps;

private:
    std::size_t index_;
    ClockDomain clock_;
    std::uint64_t cache_bits_;
    int ray_contexts_;
};

}  // namespace pp5
