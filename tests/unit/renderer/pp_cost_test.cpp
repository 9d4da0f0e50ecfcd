// Exact cycle counts of single PP operations, a QEE evaluation, a backing-store transfer and the
// slot pipeline, from the documented cost rules; and local memory that really runs out.

#include "sim/core/input_error.h"
#include "tests/unit/renderer/pp_test_support.h"

#include <gtest/gtest.h>

namespace pp5 {
namespace {

// The ALU cycles of the last instruction a builder emitted.
std::uint64_t last_cycles(const PpCostModel& model, const PpProgram& program) {
    return model.alu_cycles(program, program.instructions.back());
}

TEST(PpCost, SingleOperationsAtDefaultCosts) {
    const MachineConfig config = test::pp_config();
    const PpCostModel model(config);
    PpProgramBuilder b("ops", 208);
    const PpField u8 = b.load("u8", 0, 8, false);
    const PpField v8 = b.load("v8", 8, 8, false);
    const PpField w16 = b.load("w16", 16, 16, false);
    const PpField d9 = b.load("d9", 32, 9, false);

    PpProgram p;
    auto cycles_of = [&](auto&& emit) {
        emit();
        PpProgramBuilder copy = b;
        p = copy.finish();
        return last_cycles(model, p);
    };
    EXPECT_EQ(cycles_of([&] { b.add("sum", u8, v8); }), 9u);            // 9-bit result
    EXPECT_EQ(cycles_of([&] { b.move("copy", w16); }), 16u);
    EXPECT_EQ(cycles_of([&] { b.mul("product", u8, v8); }), 64u);      // 8 x 8
    EXPECT_EQ(cycles_of([&] { b.mul_const("times5", u8, 5); }), 24u);  // 8 bits x 3 constant bits
    EXPECT_EQ(cycles_of([&] { b.div("quotient", w16, d9, 0, 8); }), 80u);  // 8 quotient bits x (9 + 1)
    EXPECT_EQ(cycles_of([&] { b.sqrt("root", w16); }), 80u);           // 8-bit root x (8 + 2)
    EXPECT_EQ(cycles_of([&] { b.abs_diff_const("distance", u8, 40); }), 16u);
    EXPECT_EQ(cycles_of([&] { b.min_const("low", u8, 100); }), 16u);
    EXPECT_EQ(cycles_of([&] { b.enable_if(u8, PpCompare::Greater, 3); }), 8u);
    EXPECT_EQ(cycles_of([&] { b.enable_all(); }), 1u);
    // A table of 256 entries in 3 runs: 3 x (8 index bits + 4 value bits).
    PpTable steps{"steps", std::vector<std::int64_t>(256, 0)};
    for (int i = 100; i < 256; ++i) steps.entries[static_cast<std::size_t>(i)] = i < 200 ? 7 : 15;
    EXPECT_EQ(steps.runs(), 3);
    EXPECT_EQ(cycles_of([&] { b.lookup("stepped", u8, steps, 4, false); }), 36u);
    // The QEE: result bits plus its latency.
    EXPECT_EQ(cycles_of([&] { b.qee("depth", 0, 10, false, 0); }), 14u);
}

TEST(PpCost, ParametersScaleTheCosts) {
    MachineConfig config = test::pp_config();
    config.apply_override("pp.multiply_cycles_per_bit_product=1.5");
    config.apply_override("pp.qee_latency_cycles=10");
    const PpCostModel model(config);
    PpProgramBuilder b("ops", 208);
    const PpField u8 = b.load("u8", 0, 8, false);
    b.mul("square", u8, u8);
    b.qee("q", 0, 12, true, 0);
    const PpProgram p = b.finish();
    EXPECT_EQ(model.alu_cycles(p, p.instructions[1]), 96u);
    EXPECT_EQ(model.alu_cycles(p, p.instructions[2]), 22u);
}

TEST(PpCost, BackingStoreTransfersAndTheSlotPipeline) {
    const MachineConfig config = test::pp_config();
    const PpCostModel model(config);
    PpProgramBuilder b("slot", 208);
    const PpField in = b.load("record", 0, 40, false);  // 2 blocks of 32 bits
    const PpField out = b.add_const("out", in, 1);
    b.store(out, 0);                                   // 41 bits: 2 blocks
    const PpProgram p = b.finish();
    const PpProgramCost c = model.cost(p);
    EXPECT_EQ(c.load_blocks, 2u);
    EXPECT_EQ(c.store_blocks, 2u);
    EXPECT_EQ(c.load_cycles, 2u * 32u + 4u);
    EXPECT_EQ(c.store_cycles, 68u);
    EXPECT_EQ(c.alu_cycles, 41u);
    EXPECT_EQ(c.controller_cycles, 3u * 2u);

    // Transfer-bound: each middle slot waits for next load + previous store (136 > 47).
    const PpPassCycles three = model.pass(c, 3);
    EXPECT_EQ(three.total, 68u + 68u + 68u + 136u + 68u);
    EXPECT_EQ(three.alu, 3u * 41u);
    EXPECT_EQ(three.controller, 18u);
    EXPECT_EQ(three.backing_store_stall, three.total - 123u - 18u);
    const PpPassCycles one = model.pass(c, 1);
    EXPECT_EQ(one.total, 68u + 47u + 68u);

    // Compute-bound: a longer program hides the traffic except at the ends.
    PpProgramCost heavy = c;
    heavy.alu_cycles = 1000;
    const PpPassCycles hidden = model.pass(heavy, 3);
    EXPECT_EQ(hidden.total, 68u + 3u * 1006u + 68u);
    EXPECT_EQ(hidden.backing_store_stall, 136u);
    EXPECT_EQ(model.pass(c, 0).total, 0u);
}

TEST(PpLocalMemory, ProgramsFitExactlyOrSayHowFarShort) {
    PpProgramBuilder fits("fits", 208);
    for (int i = 0; i < 5; ++i) fits.alloc("a", 40, false);
    fits.alloc("b", 8, false);
    EXPECT_EQ(fits.finish().local_memory_bits_used, 208);

    PpProgramBuilder over("over", 208);
    for (int i = 0; i < 5; ++i) over.alloc("a", 40, false);
    try {
        over.alloc("extra", 9, false);
        FAIL() << "209 bits do not fit in 208";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "renderer.local_memory_bits");
        const std::string what = e.what();
        EXPECT_NE(what.find("1 bits short"), std::string::npos) << what;
        EXPECT_NE(what.find("extra"), std::string::npos) << what;
        EXPECT_NE(what.find("over"), std::string::npos) << what;
    }

    PpProgramBuilder reuse("reuse", 208);
    std::vector<PpField> fields;
    for (int i = 0; i < 5; ++i) fields.push_back(reuse.alloc("a", 40, false));
    reuse.alloc("b", 8, false);
    reuse.release(fields[1]);
    const PpField again = reuse.alloc("again", 40, false);
    EXPECT_EQ(again.offset, 40);  // the freed bits, first fit
    EXPECT_EQ(reuse.finish().local_memory_bits_used, 208);
}

TEST(PpBackingStore, RoundTripsAcrossWordBoundaries) {
    PpArray array(2, 2, 208, 200);
    array.write_backing(3, 60, 10, 0x3ABu);
    array.write_backing(3, 50, 10, 0x155u);
    array.write_backing(3, 136, 64, 0xDEADBEEFCAFEF00Dull);
    EXPECT_EQ(array.read_backing(3, 60, 10), 0x3ABu);
    EXPECT_EQ(array.read_backing(3, 50, 10), 0x155u);
    EXPECT_EQ(array.read_backing(3, 136, 64), 0xDEADBEEFCAFEF00Dull);
    EXPECT_EQ(array.read_backing(2, 60, 10), 0u);
    EXPECT_THROW(array.write_backing(3, 195, 10, 1), std::out_of_range);
    EXPECT_THROW(array.read_backing(4, 0, 8), std::out_of_range);
}

}  // namespace
}  // namespace pp5
