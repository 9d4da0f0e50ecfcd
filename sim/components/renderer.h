#pragma once
// A renderer: a SIMD array of bit-serial pixel processors (PPs), each with a little local memory and a
// larger backing store, driven by a controller and a quadratic expression evaluator. In Levoy's design
// the PPs hold the voxels and shade and classify them in parallel. Timing arrives with the renderer
// work; here it declares its parameters, its capacity and its statistics.

#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"

namespace pp5 {

class Renderer : public Component {
public:
    static const ParamGroup& params();

    Renderer(std::size_t index, const MachineConfig& config);

    std::size_t index() const { return index_; }
    const ClockDomain& clock() const { return clock_; }
    std::uint64_t pixel_processors() const { return columns_ * rows_; }
    std::uint64_t local_memory_bits() const { return local_memory_bits_; }
    std::uint64_t backing_store_bits() const { return backing_store_bits_; }

    Counter& busy_ps;
    Counter& voxel_requests;

private:
    std::size_t index_;
    ClockDomain clock_;
    std::uint64_t columns_;
    std::uint64_t rows_;
    std::uint64_t local_memory_bits_;
    std::uint64_t backing_store_bits_;
};

}  // namespace pp5
