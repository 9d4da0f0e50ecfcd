#pragma once
// Helpers for the pixel-processor tests: a configuration with the default costs, and a way to run a
// one-instruction program over every combination of operands, one combination per PP.

#include "sim/components/renderer.h"
#include "sim/core/calibration.h"
#include "sim/core/config.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_cost_model.h"
#include "sim/pixel_processors/pp_program.h"

#include <functional>
#include <vector>

namespace pp5::test {

inline MachineConfig pp_config() {
    return MachineConfig({&Renderer::params(), &PpCostModel::params(), &CalibrationScales::params()});
}

// Operands for each PP, loaded from its backing store (a at bit 0, b at bit 32).
struct Operands {
    PpField a;
    PpField b;
};

// Runs `body` (which emits the instruction under test and returns its result field) over one PP per
// (a, b) pair, a and b taking every value of their widths; returns the result per PP, PP index =
// ia + ib * count_a, where ia, ib index the operand values from their minimum.
inline std::vector<std::int64_t> run_exhaustive(int a_bits, bool a_signed, int b_bits, bool b_signed,
                                                const std::function<PpField(PpProgramBuilder&, Operands)>& body,
                                                PpProgram* program_out = nullptr) {
    const std::int64_t count_a = std::int64_t{1} << a_bits;
    const std::int64_t count_b = b_bits > 0 ? std::int64_t{1} << b_bits : 1;
    const std::int64_t pps = count_a * count_b;
    const int columns = static_cast<int>(std::min<std::int64_t>(pps, 256));
    PpArray array(columns, static_cast<int>(pps / columns), 208, 64);
    const std::int64_t a_min = a_signed ? -(count_a / 2) : 0;
    const std::int64_t b_min = b_signed ? -(count_b / 2) : 0;
    for (std::int64_t p = 0; p < pps; ++p) {
        array.write_backing(static_cast<int>(p), 0, a_bits, static_cast<std::uint64_t>(a_min + p % count_a));
        if (b_bits > 0)
            array.write_backing(static_cast<int>(p), 32, b_bits, static_cast<std::uint64_t>(b_min + p / count_a));
    }
    PpProgramBuilder builder("exhaustive", 208);
    Operands ops;
    ops.a = builder.load("a", 0, a_bits, a_signed);
    if (b_bits > 0) ops.b = builder.load("b", 32, b_bits, b_signed);
    const PpField result = body(builder, ops);
    PpProgram program = builder.finish();
    array.run(program, PpSlotContext{});
    auto values = array.field_values(result);
    if (program_out != nullptr) *program_out = program;
    return {values.begin(), values.end()};
}

}  // namespace pp5::test
