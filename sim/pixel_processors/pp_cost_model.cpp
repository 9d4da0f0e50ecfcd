#include "sim/pixel_processors/pp_cost_model.h"

#include "sim/core/calibration.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace pp5 {

namespace {

// factor x work rounded up to whole cycles. A product that is a whole number up to rounding error
// (1.1 x 50 = 55.000000000000007 in binary floating point) counts as that number, not the next.
std::uint64_t cycles(double factor, std::uint64_t work) {
    const double exact = factor * static_cast<double>(work);
    const double nearest = std::round(exact);
    // The factor's representation and the product each err by at most half an ulp: 4 epsilon is ample.
    const double tolerance = 4 * std::numeric_limits<double>::epsilon() * std::max(1.0, exact);
    const double rounded = std::abs(exact - nearest) <= tolerance ? nearest : std::ceil(exact);
    return static_cast<std::uint64_t>(rounded);
}

std::uint64_t bits_of(const PpProgram& program, int id) {
    return static_cast<std::uint64_t>(program.fields[static_cast<std::size_t>(id)].bits);
}

}  // namespace

const ParamGroup& PpCostModel::params() {
    static const ParamGroup group = [] {
        ParamGroup g("pp", "Pixel-processor array timing: operation costs, QEE, controller and backing store");
        g.all_timing_only();  // it changes when work happens, never what is computed
        g.real("cycles_per_bit", 1.0, "cycles", 0.01, 100,
               "Cycles per result bit of a bit-serial add, subtract, compare or move", Provenance::Default,
               "machine.md: about one cycle per operand bit for add/compare/move ([D])")
            .plausible(1, 2,
                       "a bit-serial ALU does at most a bit a cycle; a separate carry or load cycle would double it")
            .real("multiply_cycles_per_bit_product", 1.0, "cycles", 0.01, 100,
                  "Cycles per pair of operand bits of a multiply (an n x m multiply takes about n*m)",
                  Provenance::Default, "machine.md: about n^2 cycles for an n x n multiply ([D])")
            .plausible(0.5, 2,
                       "shift-and-add is one add per multiplier bit; skipping zero bits halves it, "
                       "a load of each partial product doubles it")
            .real("divide_cycles_per_bit_product", 1.0, "cycles", 0.01, 100,
                  "Cycles per result bit times trial-subtraction width of a restoring divide or square root",
                  Provenance::Default,
                  "machine.md: about one cycle per operand bit for add/compare ([D]); a restoring divide or square "
                  "root does one trial subtraction per result bit")
            .plausible(0.5, 2, "as the multiply: a trial subtraction a result bit, with or without a restore")
            .integer("qee_latency_cycles", 4, "cycles", 0, 1000,
                     "Pipeline latency of the quadratic expression evaluator, on top of one cycle per result bit",
                     Provenance::Default, "machine.md: QEE about (bits + a few) cycles per expression ([D])")
            .plausible(1, 16, "'a few' cycles of pipeline: one stage to a tree of 16")
            .integer("controller_cycles_per_instruction", 2, "cycles", 0, 1000,
                     "Cycles the renderer's controller adds to each instruction it issues", Provenance::Default,
                     "machine.md: the renderer controller turns ring messages into micro-instructions ([D]); "
                     "its issue cost is not published")
            .plausible(
                0, 4,
                "a controller that overlaps decoding with execution adds nothing; one that does not, a few cycles")
            .integer("backing_store_cycles_per_block", 32, "cycles", 1, 100000,
                     "Cycles to move one block between a PP's local memory and its backing store", Provenance::Default,
                     "machine.md: backing store moved in 32-bit blocks, slower than local memory ([S]); a block "
                     "entering the bit-organised local memory one bit per cycle is our default ([D])")
            .plausible(16, 128,
                       "two bits a cycle (a wide video RAM port) to four cycles a bit ('slower than local memory')")
            .integer("backing_store_setup_cycles", 4, "cycles", 0, 100000,
                     "Cycles to start a slot's backing-store transfer in either direction", Provenance::Default,
                     "machine.md: transfers asynchronous and overlapping compute ([S]); the start-up cost is not "
                     "published ([D])")
            .plausible(0, 16, "asynchronous transfers may start for free or after a row access of a video RAM");
        return g;
    }();
    return group;
}

PpCostModel::PpCostModel(const MachineConfig& config)
    : cycles_per_bit_(config.real("pp.cycles_per_bit")),
      multiply_cycles_per_bit_product_(config.real("pp.multiply_cycles_per_bit_product")),
      divide_cycles_per_bit_product_(config.real("pp.divide_cycles_per_bit_product")),
      qee_latency_cycles_(static_cast<std::uint64_t>(config.integer("pp.qee_latency_cycles"))),
      controller_cycles_per_instruction_(
          static_cast<std::uint64_t>(config.integer("pp.controller_cycles_per_instruction"))),
      backing_store_block_bits_(static_cast<std::uint64_t>(config.integer("renderer.backing_store_block_bits"))),
      backing_store_cycles_per_block_(static_cast<std::uint64_t>(config.integer("pp.backing_store_cycles_per_block"))),
      backing_store_setup_cycles_(static_cast<std::uint64_t>(config.integer("pp.backing_store_setup_cycles"))),
      scale_(CalibrationScales::from(config).pp_cycles) {}

std::uint64_t PpCostModel::alu_cycles(const PpProgram& program, const PpInstruction& in) const {
    const std::uint64_t n = in.dst >= 0 ? bits_of(program, in.dst) : 0;
    const std::uint64_t a = in.a >= 0 ? bits_of(program, in.a) : 0;
    const std::uint64_t b = in.b >= 0 ? bits_of(program, in.b) : 0;
    switch (in.op) {
        case PpOp::SetConst:
        case PpOp::Move:
        case PpOp::Add:
        case PpOp::Sub:
        case PpOp::AddConst: return cycles(cycles_per_bit_, n);
        case PpOp::AbsDiffConst:  // subtract, then negate where negative
            return cycles(cycles_per_bit_, 2 * n);
        case PpOp::MinConst:
        case PpOp::MaxConst:  // compare, then move where the constant wins
            return cycles(cycles_per_bit_, 2 * a);
        case PpOp::Mul: return cycles(multiply_cycles_per_bit_product_, a * b);
        case PpOp::MulConst: {
            // Shift-and-add over the broadcast constant's bits.
            const auto raw = static_cast<std::uint64_t>(in.imm);
            const std::uint64_t magnitude = in.imm < 0 ? ~raw + 1 : raw;  // |imm|, defined for the most negative too
            const auto constant_bits =
                static_cast<std::uint64_t>(std::max(1, static_cast<int>(std::bit_width(magnitude))));
            return cycles(multiply_cycles_per_bit_product_, a * constant_bits);
        }
        case PpOp::Div:  // one trial subtraction of the divisor's width (plus a bit) per quotient bit
            return cycles(divide_cycles_per_bit_product_, n * (b + 1));
        case PpOp::Sqrt:  // one trial subtraction of about the root's width per root bit
            return cycles(divide_cycles_per_bit_product_, n * (n + 2));
        case PpOp::Lookup: {
            // Per run of equal entries: compare the index with the run's start, move the value where reached.
            const auto runs = static_cast<std::uint64_t>(program.tables[static_cast<std::size_t>(in.table)].runs());
            return cycles(cycles_per_bit_, runs * (a + n));
        }
        case PpOp::Qee: return n + qee_latency_cycles_;
        case PpOp::EnableAll: return 1;
        case PpOp::EnableIf: return cycles(cycles_per_bit_, a);
        case PpOp::Load:
        case PpOp::Store: return 0;  // the backing-store port moves these, beside the ALUs
    }
    return 0;
}

PpProgramCost PpCostModel::cost(const PpProgram& program) const {
    PpProgramCost c;
    for (const PpInstruction& in : program.instructions) {
        c.alu_cycles += alu_cycles(program, in);
        c.controller_cycles += controller_cycles_per_instruction_;
        const auto blocks_of = [&](int id) {
            return (bits_of(program, id) + backing_store_block_bits_ - 1) / backing_store_block_bits_;
        };
        if (in.op == PpOp::Load) c.load_blocks += blocks_of(in.dst);
        if (in.op == PpOp::Store) c.store_blocks += blocks_of(in.a);
    }
    c.load_cycles =
        c.load_blocks * backing_store_cycles_per_block_ + (c.load_blocks > 0 ? backing_store_setup_cycles_ : 0);
    c.store_cycles =
        c.store_blocks * backing_store_cycles_per_block_ + (c.store_blocks > 0 ? backing_store_setup_cycles_ : 0);
    if (scale_ != 1.0) {  // the calibration's factor over every documented PP cost
        for (std::uint64_t* part : {&c.alu_cycles, &c.controller_cycles, &c.load_cycles, &c.store_cycles})
            *part = cycles(scale_, *part);
    }
    return c;
}

PpPassCycles PpCostModel::pass(const PpProgramCost& cost, std::uint64_t slots) const {
    PpPassCycles p;
    if (slots == 0) return p;
    // Slots run one after another. While slot k computes, the backing-store port brings in slot k+1's
    // inputs and writes out slot k-1's results, so a slot takes the longer of its computation and that
    // traffic; nothing hides the first slot's load or the last slot's store:
    //
    //   total = L + sum over k = 0 .. S-1 of max(C, L [k < S-1] + W [k > 0]) + W
    //
    // with C = compute (ALU + controller), L = load cycles, W = store cycles, S = slots. For S = 1 that
    // is L + C + W; for S >= 2, L + max(C, L) + (S - 2) max(C, L + W) + max(C, W) + W. Whatever of the
    // total is not ALU or controller time is backing-store stall.
    const std::uint64_t compute = cost.compute_cycles();
    const std::uint64_t load = cost.load_cycles;
    const std::uint64_t store = cost.store_cycles;
    p.total = load + store;
    if (slots == 1) {
        p.total += compute;
    } else {  // the first slot, the slots - 2 middle ones, the last: O(1) for any number of slots
        p.total += std::max(compute, load) + (slots - 2) * std::max(compute, load + store) + std::max(compute, store);
    }
    p.alu = slots * cost.alu_cycles;
    p.controller = slots * cost.controller_cycles;
    p.backing_store_stall = p.total - p.alu - p.controller;
    return p;
}

}  // namespace pp5
