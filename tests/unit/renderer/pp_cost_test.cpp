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
    PpProgramBuilder b("ops", 4096);  // room for every result at once: this test is about cycles
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
    const PpField u7 = b.load("u7", 48, 7, false);
    const PpField w7 = b.load("w7", 56, 7, false);
    EXPECT_EQ(cycles_of([&] { b.add("sum8", u7, w7); }), 8u);        // an 8-bit add: [0, 254]
    EXPECT_EQ(cycles_of([&] { b.add("sum", u8, v8); }), 9u);         // 9-bit result
    EXPECT_EQ(cycles_of([&] { b.sub("difference", u8, v8); }), 9u);  // [-255, 255]: 9 bits signed
    EXPECT_EQ(cycles_of([&] { b.add_const("plus", u8, 1); }), 9u);   // [1, 256]
    EXPECT_EQ(cycles_of([&] { b.set_const("k", 100); }), 7u);
    EXPECT_EQ(cycles_of([&] { b.max_const("high", u8, 3); }), 16u);        // 2 x 8 operand bits
    EXPECT_EQ(cycles_of([&] { b.mul_const("negated", u8, -5); }), 24u);    // |-5| has 3 bits
    EXPECT_EQ(cycles_of([&] { b.mul_const("zero", u8, 0); }), 8u);         // at least one constant bit
    EXPECT_EQ(cycles_of([&] { b.mul_const("times256", u8, 256); }), 72u);  // 9 constant bits
    EXPECT_EQ(cycles_of([&] { b.store(u8, 100); }), 0u);                   // the backing-store port's, not the ALU's
    EXPECT_EQ(cycles_of([&] { b.load("more", 120, 16, false); }), 0u);
    EXPECT_EQ(cycles_of([&] { b.move("copy", w16); }), 16u);
    EXPECT_EQ(cycles_of([&] { b.mul("product", u8, v8); }), 64u);          // 8 x 8
    EXPECT_EQ(cycles_of([&] { b.mul_const("times5", u8, 5); }), 24u);      // 8 bits x 3 constant bits
    EXPECT_EQ(cycles_of([&] { b.div("quotient", w16, d9, 0, 8); }), 80u);  // 8 quotient bits x (9 + 1)
    EXPECT_EQ(cycles_of([&] { b.sqrt("root", w16); }), 80u);               // 8-bit root x (8 + 2)
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

TEST(PpCost, SixtyFourBitsOfLoadsAreTwoBlocks) {
    // Two 32-bit loads (a field holds at most 48 bits): 2 blocks, 2 x 32 cycles + one setup of 4.
    const PpCostModel model(test::pp_config());
    PpProgramBuilder b("loads", 208);
    b.load("low", 0, 32, false);
    b.load("high", 32, 32, false);
    const PpProgramCost c = model.cost(b.finish());
    EXPECT_EQ(c.load_blocks, 2u);
    EXPECT_EQ(c.load_cycles, 2u * 32u + 4u);
    EXPECT_EQ(c.store_blocks, 0u);
    EXPECT_EQ(c.store_cycles, 0u);  // no stores, no setup
    EXPECT_EQ(c.alu_cycles, 0u);
    EXPECT_EQ(c.controller_cycles, 4u);

    // Each load rounds up to whole blocks: 33 bits and 1 bit are 2 + 1 blocks.
    PpProgramBuilder odd("odd", 208);
    odd.load("wide", 0, 33, false);
    odd.load("flag", 40, 1, false);
    EXPECT_EQ(model.cost(odd.finish()).load_blocks, 3u);
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

TEST(PpCost, EveryParameterComesFromTheConfiguration) {
    MachineConfig config = test::pp_config();
    config.set("pp.cycles_per_bit", 1.5, "test");
    config.set("pp.divide_cycles_per_bit_product", 2.0, "test");
    config.set("pp.controller_cycles_per_instruction", std::int64_t{5}, "test");
    config.set("pp.backing_store_cycles_per_block", std::int64_t{10}, "test");
    config.set("pp.backing_store_setup_cycles", std::int64_t{7}, "test");
    config.apply_override("renderer.backing_store_block_bits=16");
    const PpCostModel model(config);
    PpProgramBuilder b("ops", 208);
    const PpField u8 = b.load("u8", 0, 8, false);
    const PpField w16 = b.load("w16", 8, 16, false);
    const PpField d9 = b.load("d9", 24, 9, false);
    const PpField r40 = b.load("r40", 40, 40, false);
    b.add("sum", u8, u8);       // 9 bits x 1.5 = 13.5: 14
    b.div("q", w16, d9, 0, 8);  // 8 x 10 x 2 = 160
    b.store(r40, 100);          // 40 bits in 16-bit blocks: 3
    const PpProgram p = b.finish();
    EXPECT_EQ(model.alu_cycles(p, p.instructions[4]), 14u);
    EXPECT_EQ(model.alu_cycles(p, p.instructions[5]), 160u);
    const PpProgramCost c = model.cost(p);
    EXPECT_EQ(c.controller_cycles, 7u * 5u);
    EXPECT_EQ(c.load_blocks, 1u + 1u + 1u + 3u);
    EXPECT_EQ(c.load_cycles, 6u * 10u + 7u);
    EXPECT_EQ(c.store_blocks, 3u);
    EXPECT_EQ(c.store_cycles, 3u * 10u + 7u);
}

TEST(PpCost, FractionalFactorsRoundUpToWholeCyclesWithoutFloatingPointError) {
    MachineConfig config = test::pp_config();
    config.apply_override("pp.cycles_per_bit=1.1");
    const PpCostModel model(config);
    PpProgramBuilder b("round", 208);
    const PpField u8 = b.load("u8", 0, 8, false);
    const PpField index = b.load("index", 8, 2, false);
    b.add_const("s", u8, 1);       // 9 bits x 1.1 = 9.9: 10
    b.abs_diff_const("d", u8, 0);  // 2 x 8 x 1.1 = 17.6: 18
    // 1 run x (2 index bits + 48 value bits) = 50; 1.1 x 50 is 55.000000000000007 in doubles: 55, not 56.
    b.lookup("value", index, PpTable{"flat", std::vector<std::int64_t>(4, 0)}, 48, false);
    const PpProgram p = b.finish();
    EXPECT_EQ(model.alu_cycles(p, p.instructions[2]), 10u);
    EXPECT_EQ(model.alu_cycles(p, p.instructions[3]), 18u);
    EXPECT_EQ(model.alu_cycles(p, p.instructions[4]), 55u);
}

TEST(PpCost, ParameterTableDocumentsEveryKey) {
    const ParamGroup& g = PpCostModel::params();
    EXPECT_EQ(g.prefix(), "pp");
    const std::vector<std::string> keys = {"cycles_per_bit",
                                           "multiply_cycles_per_bit_product",
                                           "divide_cycles_per_bit_product",
                                           "qee_latency_cycles",
                                           "controller_cycles_per_instruction",
                                           "backing_store_cycles_per_block",
                                           "backing_store_setup_cycles"};
    ASSERT_EQ(g.specs().size(), keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const ParamSpec& spec = g.specs()[i];
        EXPECT_EQ(spec.name, keys[i]);
        EXPECT_FALSE(spec.unit.empty()) << spec.name;
        EXPECT_FALSE(spec.doc.empty()) << spec.name;
        EXPECT_TRUE(spec.min.has_value() && spec.max.has_value()) << spec.name;
        EXPECT_EQ(spec.provenance, Provenance::Default) << spec.name;
        EXPECT_NE(spec.source.find("machine.md"), std::string::npos) << spec.name << ": " << spec.source;
        EXPECT_TRUE(spec.check(spec.default_value).empty()) << spec.name;
    }
    const MachineConfig config = test::pp_config();
    EXPECT_EQ(config.real("pp.cycles_per_bit"), 1.0);
    EXPECT_EQ(config.real("pp.multiply_cycles_per_bit_product"), 1.0);
    EXPECT_EQ(config.real("pp.divide_cycles_per_bit_product"), 1.0);
    EXPECT_EQ(config.integer("pp.qee_latency_cycles"), 4);
    EXPECT_EQ(config.integer("pp.controller_cycles_per_instruction"), 2);
    EXPECT_EQ(config.integer("pp.backing_store_cycles_per_block"), 32);
    EXPECT_EQ(config.integer("pp.backing_store_setup_cycles"), 4);
}

TEST(PpCost, BackingStoreTransfersAndTheSlotPipeline) {
    const MachineConfig config = test::pp_config();
    const PpCostModel model(config);
    PpProgramBuilder b("slot", 208);
    const PpField in = b.load("record", 0, 40, false);  // 2 blocks of 32 bits
    const PpField out = b.add_const("out", in, 1);
    b.store(out, 0);  // 41 bits: 2 blocks
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
    const PpPassCycles hidden_one = model.pass(heavy, 1);
    EXPECT_EQ(hidden_one.total, 68u + 1006u + 68u);
    EXPECT_EQ(hidden_one.alu, 1000u);
    EXPECT_EQ(hidden_one.controller, 6u);
    EXPECT_EQ(hidden_one.backing_store_stall, 136u);

    // Between the two: compute 100 hides a load (68) or a store (68) alone, not both (136).
    PpProgramCost middle = c;
    middle.alu_cycles = 94;
    EXPECT_EQ(model.pass(middle, 3).total, 68u + 100u + 136u + 100u + 68u);
    EXPECT_EQ(model.pass(middle, 2).total, 68u + 100u + 100u + 68u);

    const PpPassCycles none = model.pass(c, 0);
    EXPECT_EQ(none.total, 0u);
    EXPECT_EQ(none.alu, 0u);
    EXPECT_EQ(none.controller, 0u);
    EXPECT_EQ(none.backing_store_stall, 0u);
}

TEST(PpCost, PassIsTheSlotBySlotSum) {
    // The closed form against the definition, slot by slot, over loads, stores and computations
    // on either side of each other.
    const PpCostModel model(test::pp_config());
    for (std::uint64_t load : {0u, 36u, 68u, 500u}) {
        for (std::uint64_t store : {0u, 36u, 300u}) {
            for (std::uint64_t alu : {0u, 50u, 400u}) {
                PpProgramCost c;
                c.alu_cycles = alu;
                c.controller_cycles = 10;
                c.load_cycles = load;
                c.store_cycles = store;
                for (std::uint64_t slots : {1u, 2u, 3u, 7u, 64u}) {
                    std::uint64_t want = load + store;
                    for (std::uint64_t k = 0; k < slots; ++k) {
                        want += std::max(alu + 10, (k + 1 < slots ? load : 0) + (k > 0 ? store : 0));
                    }
                    const PpPassCycles got = model.pass(c, slots);
                    EXPECT_EQ(got.total, want) << load << " " << store << " " << alu << " " << slots;
                    EXPECT_EQ(got.total, got.alu + got.controller + got.backing_store_stall);
                }
            }
        }
    }
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
        EXPECT_NE(what.find("needs 209 bits"), std::string::npos) << what;
        EXPECT_NE(what.find("has 208 (1 bit short)"), std::string::npos) << what;
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
