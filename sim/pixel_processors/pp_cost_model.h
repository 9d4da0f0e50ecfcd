#pragma once
// What a PP program costs on a renderer, in PP clock cycles, from the operand widths of each
// instruction (bit-serial arithmetic takes about a cycle per bit, a multiply about one per pair of
// bits), plus the controller's issue overhead and the backing-store traffic of a voxel slot. The
// constants are parameters ("pp.*") with documented provenance; the calibration fits them.
//
// A renderer runs one program over many voxel slots; backing-store transfers for the next slot
// overlap the computation of this one, so a slot costs the larger of its computation and its
// transfers, plus the first load and the last store that nothing hides.

#include "sim/core/config.h"
#include "sim/core/param.h"
#include "sim/pixel_processors/pp_program.h"

#include <cstdint>

namespace pp5 {

struct PpProgramCost {
    std::uint64_t alu_cycles = 0;         // the PPs computing
    std::uint64_t controller_cycles = 0;  // instruction issue overhead
    std::uint64_t load_blocks = 0;        // backing-store blocks moved in per slot
    std::uint64_t store_blocks = 0;       // and out
    std::uint64_t load_cycles = 0;
    std::uint64_t store_cycles = 0;

    std::uint64_t compute_cycles() const { return alu_cycles + controller_cycles; }
    std::uint64_t transfer_cycles() const { return load_cycles + store_cycles; }
};

// The time of a program run over `slots` slots one after another, split by what the renderer was
// doing: computing, issuing, or waiting for backing-store transfers not hidden under computation.
struct PpPassCycles {
    std::uint64_t total = 0;
    std::uint64_t alu = 0;
    std::uint64_t controller = 0;
    std::uint64_t backing_store_stall = 0;
};

class PpCostModel {
public:
    static const ParamGroup& params();

    explicit PpCostModel(const MachineConfig& config);

    // Cycles of one instruction of `program` on the PP ALUs (0 for Load and Store, which the
    // backing-store port moves).
    std::uint64_t alu_cycles(const PpProgram& program, const PpInstruction& instruction) const;
    PpProgramCost cost(const PpProgram& program) const;
    PpPassCycles pass(const PpProgramCost& cost, std::uint64_t slots) const;

private:
    double cycles_per_bit_;
    double multiply_cycles_per_bit_product_;
    double divide_cycles_per_bit_product_;
    std::uint64_t qee_latency_cycles_;
    std::uint64_t controller_cycles_per_instruction_;
    std::uint64_t backing_store_block_bits_;
    std::uint64_t backing_store_cycles_per_block_;
    std::uint64_t backing_store_setup_cycles_;
    double scale_;  // calibration.pp_cycles_scale
};

}  // namespace pp5
