// The PP program builder: result widths inferred from value ranges, the instructions it emits, what
// it refuses (bad widths, dead fields, shifts, tables, signed divides, results past 64 bits), and
// local memory allocated first-fit with a clear error when a program does not fit.

#include "sim/core/input_error.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_program.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <set>
#include <stdexcept>

namespace pp5 {
namespace {

using ::testing::HasSubstr;

// Runs `f`, expects std::invalid_argument, and returns its message.
template <class F>
std::string invalid_argument_message(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    ADD_FAILURE() << "no std::invalid_argument";
    return {};
}

TEST(PpWidths, BitsForRange) {
    EXPECT_EQ(pp_bits_for_range(0, 0), 1);
    EXPECT_EQ(pp_bits_for_range(0, 1), 1);
    EXPECT_EQ(pp_bits_for_range(-1, 0), 1);
    EXPECT_EQ(pp_bits_for_range(-1, -1), 1);
    EXPECT_EQ(pp_bits_for_range(0, 255), 8);
    EXPECT_EQ(pp_bits_for_range(0, 256), 9);
    EXPECT_EQ(pp_bits_for_range(-128, 127), 8);
    EXPECT_EQ(pp_bits_for_range(-129, 0), 9);
    EXPECT_EQ(pp_bits_for_range(-128, 128), 9);
    EXPECT_EQ(pp_bits_for_range(127, -128), 8);  // either order
    EXPECT_EQ(pp_bits_for_range(0, (std::int64_t{1} << 47) - 1), 47);
    EXPECT_EQ(pp_bits_for_range(0, std::numeric_limits<std::int64_t>::max()), 63);
    EXPECT_EQ(pp_bits_for_range(std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()),
              64);
}

TEST(PpWidths, EachOperationsResultFromItsOperandRanges) {
    PpProgramBuilder b("widths", 4096);
    const PpField u8 = b.load("u8", 0, 8, false);
    const PpField u9 = b.load("u9", 8, 9, false);
    const PpField s8 = b.load("s8", 17, 8, true);
    const PpField u16 = b.load("u16", 32, 16, false);

    auto expect = [](PpField f, int bits, bool is_signed) {
        EXPECT_EQ(f.bits, bits);
        EXPECT_EQ(f.is_signed, is_signed);
    };
    expect(b.add("a", u8, u9), 10, false);             // [0, 766]: the header's example
    expect(b.sub("b", u8, u8), 1, false);              // x - x is 0
    expect(b.sub("c", u8, u9), 10, true);              // [-511, 255]
    expect(b.add_const("d", s8, 128), 8, false);       // [0, 255]
    expect(b.add_const("e", u8, -256), 9, true);       // [-256, -1]
    expect(b.abs_diff_const("f", u8, 40), 8, false);   // [0, 215]
    expect(b.abs_diff_const("g", u8, 300), 9, false);  // [45, 300]
    expect(b.min_const("h", u8, 100), 7, false);       // [0, 100]
    expect(b.max_const("i", s8, 0), 7, false);         // [0, 127]
    expect(b.max_const("j", s8, -200), 8, true);       // unchanged: [-128, 127]
    expect(b.move("k", s8, 3), 5, true);               // [-16, 15]
    expect(b.move("l", u16, 15), 1, false);            // [0, 1]
    expect(b.mul("m", u8, s8), 16, true);              // [-32640, 32385]
    expect(b.mul("n", s8, s8), 15, false);             // a square: [0, 16384]
    expect(b.mul("o", u8, u9, 8), 9, false);           // [0, 130305] >> 8 = [0, 509]
    expect(b.mul("p", s8, u8, 4), 12, true);           // [-32640, 32385] >> 4 = [-2040, 2024]
    expect(b.mul_const("q", u8, -3), 11, true);        // [-765, 0]
    expect(b.mul_const("r", u8, 5, 2), 9, false);      // [0, 1275] >> 2 = [0, 318]
    expect(b.mul_const("s", u8, 0), 1, false);         // 0
    expect(b.div("t", u8, u9, 6, 12), 12, false);      // declared, unsigned
    expect(b.sqrt("u", u16), 8, false);                // [0, 255]
    expect(b.sqrt("v", s8), 4, false);                 // [0, 11]
    expect(b.qee("w", 0, 20, true, 3), 20, true);      // declared
    expect(b.set_const("x", 0), 1, false);
    expect(b.set_const("y", -1), 1, true);
    expect(b.set_const("z", 255), 8, false);
    expect(b.set_const("zz", 255, 16, true), 16, true);  // declared
    PpTable table{"t", std::vector<std::int64_t>(256, 3)};
    expect(b.lookup("lut", u8, table, 5, true), 5, true);  // declared
    // A result's range, not its width, feeds the next: [0, 100] + [0, 100] = [0, 200], 8 bits.
    const PpField h = b.min_const("h2", u8, 100);
    expect(b.add("hh", h, h), 8, false);
    // A lookup's range is its entries' range: all 3, so 3 + 3 is 6, 3 bits.
    const PpField three = b.lookup("three", u8, table, 8, false);
    expect(b.add("six", three, three), 3, false);
}

TEST(PpWidths, SumOfThreeSquaresOfSignedBytes) {
    PpProgramBuilder b("gradient", 208);
    const PpField gx = b.load("gx", 0, 8, true);
    const PpField gy = b.load("gy", 8, 8, true);
    const PpField gz = b.load("gz", 16, 8, true);
    // As squares: 3 x 128^2 = 49152, 16 bits unsigned.
    const PpField squares = b.add("s", b.add("s2", b.mul("x2", gx, gx), b.mul("y2", gy, gy)), b.mul("z2", gz, gz));
    EXPECT_EQ(squares.bits, 16);
    EXPECT_FALSE(squares.is_signed);
    EXPECT_EQ(b.sqrt("magnitude", squares).bits, 8);  // floor(sqrt(49152)) = 221
    // As general products of independent fields, each [-16256, 16384]: the sum fits 17 bits signed.
    const PpField products = b.add("p", b.add("p2", b.mul("xy", gx, gy), b.mul("yz", gy, gz)), b.mul("zx", gz, gx));
    EXPECT_EQ(products.bits, 17);
    EXPECT_TRUE(products.is_signed);
}

TEST(PpBuilder, EmitsOneInstructionPerOperation) {
    PpProgramBuilder b("emit", 208);
    const PpField a = b.load("a", 16, 8, true);
    const PpField s = b.mul_const("s", a, -3, 1);
    b.enable_if(s, PpCompare::Less, 7);
    const PpField q = b.qee("q", 2, 10, false, 4);
    b.store(q, 40);
    b.enable_all();
    const PpProgram p = b.finish();
    EXPECT_EQ(p.name, "emit");
    ASSERT_EQ(p.instructions.size(), 6u);
    EXPECT_EQ(p.instructions[0].op, PpOp::Load);
    EXPECT_EQ(p.instructions[0].dst, a.id);
    EXPECT_EQ(p.instructions[0].record_offset, 16);
    EXPECT_EQ(p.instructions[1].op, PpOp::MulConst);
    EXPECT_EQ(p.instructions[1].a, a.id);
    EXPECT_EQ(p.instructions[1].imm, -3);
    EXPECT_EQ(p.instructions[1].shift, 1);
    EXPECT_EQ(p.instructions[2].op, PpOp::EnableIf);
    EXPECT_EQ(p.instructions[2].compare, PpCompare::Less);
    EXPECT_EQ(p.instructions[2].imm, 7);
    EXPECT_EQ(p.instructions[3].op, PpOp::Qee);
    EXPECT_EQ(p.instructions[3].expression, 2);
    EXPECT_EQ(p.instructions[4].op, PpOp::Store);
    EXPECT_EQ(p.instructions[4].a, q.id);
    EXPECT_EQ(p.instructions[5].op, PpOp::EnableAll);
    EXPECT_EQ(p.expressions, 3);  // expression 2 needs three
    ASSERT_EQ(p.fields.size(), 3u);
    EXPECT_EQ(p.field_names[static_cast<std::size_t>(s.id)], "s");
}

TEST(PpBuilder, AssignChecksTheValueFitsAndWidensTheDestinationsRange) {
    PpProgramBuilder b("assign", 208);
    const PpField small = b.load("small", 0, 4, false);  // [0, 15]
    const PpField r = b.set_const("r", 0, 8, false);     // holds 0 so far
    EXPECT_EQ(b.add_const("before", r, 1).bits, 1);      // [1, 1]
    b.assign(r, small);                                  // now [0, 15]
    EXPECT_EQ(b.add_const("after", r, 1).bits, 5);       // [1, 16]
    b.assign_const(r, 200);                              // now [0, 200]
    EXPECT_EQ(b.add_const("later", r, 1).bits, 8);       // [1, 201]

    const PpField wide = b.load("wide", 8, 9, false);
    EXPECT_THAT(invalid_argument_message([&] { b.assign(r, wide); }), HasSubstr("may not fit r"));
    EXPECT_THAT(invalid_argument_message([&] { b.assign_const(r, 256); }), HasSubstr("256 does not fit r"));
    EXPECT_THAT(invalid_argument_message([&] { b.assign_const(r, -1); }), HasSubstr("does not fit r"));
    const PpField negative = b.set_const("negative", -1);
    EXPECT_THROW(b.assign(r, negative), std::invalid_argument);

    const PpProgram p = b.finish();
    // assign and assign_const write the existing field: a Move and a SetConst into r.
    int writes_to_r = 0;
    for (const PpInstruction& in : p.instructions) {
        if (in.dst == r.id) {
            ++writes_to_r;
            EXPECT_TRUE(in.op == PpOp::SetConst || in.op == PpOp::Move) << to_string(in.op);
        }
    }
    EXPECT_EQ(writes_to_r, 3);  // set_const, assign, assign_const
}

TEST(PpBuilder, RejectsFieldWidthsOutsideOneToFortyEight) {
    PpProgramBuilder b("widths", 4096);
    EXPECT_EQ(b.alloc("widest", kMaxPpFieldBits, true).bits, 48);
    EXPECT_EQ(b.alloc("narrowest", 1, false).bits, 1);
    EXPECT_THAT(invalid_argument_message([&] { b.alloc("zero", 0, false); }),
                HasSubstr("zero of 0 bits (1 to 48 allowed)"));
    EXPECT_THAT(invalid_argument_message([&] { b.alloc("wide", 49, false); }), HasSubstr("wide of 49 bits"));
    EXPECT_THROW(b.load("l", 0, 0, false), std::invalid_argument);
    EXPECT_THROW(b.set_const("c", 0, 49, true), std::invalid_argument);
    EXPECT_THROW(b.qee("q", 0, 60, true, 0), std::invalid_argument);
    const PpField u8 = b.load("u8", 0, 8, false);
    EXPECT_THROW(b.div("d", u8, u8, 0, 0), std::invalid_argument);
    EXPECT_THROW(b.lookup("t", u8, PpTable{"t", std::vector<std::int64_t>(256, 0)}, 49, false), std::invalid_argument);
    // A value that does not fit its declared field.
    EXPECT_THAT(invalid_argument_message([&] { b.set_const("c", 128, 8, true); }),
                HasSubstr("128 does not fit field c"));
    EXPECT_THROW(b.set_const("c", -1, 8, false), std::invalid_argument);
    // A constant too wide for any field.
    EXPECT_THROW(b.set_const("huge", std::int64_t{1} << 50), std::invalid_argument);
}

TEST(PpBuilder, RejectsResultsWiderThanAnyField) {
    PpProgramBuilder b("wide", 4096);
    const PpField s30 = b.load("s30", 0, 30, true);
    const PpField t30 = b.load("t30", 30, 30, true);
    const PpField w48 = b.load("w48", 60, 48, true);
    // [-2^29 (2^29 - 1), 2^58]: 60 bits signed, more than a field holds.
    EXPECT_THAT(invalid_argument_message([&] { b.mul("p", s30, t30); }),
                HasSubstr("field p of 60 bits (1 to 48 allowed)"));
    EXPECT_THAT(invalid_argument_message([&] { b.add("s", w48, w48); }), HasSubstr("field s of 49 bits"));
    // Ranges past 64 bits are refused without overflowing (no undefined behaviour).
    EXPECT_THAT(invalid_argument_message([&] { b.mul("q", w48, s30); }),
                HasSubstr("values of field q would need more than 64 bits"));
    const auto top = std::numeric_limits<std::int64_t>::max();
    const auto bottom = std::numeric_limits<std::int64_t>::min();
    EXPECT_THAT(invalid_argument_message([&] { b.mul_const("m", w48, top); }), HasSubstr("more than 64 bits"));
    EXPECT_THAT(invalid_argument_message([&] { b.add_const("a", w48, top); }), HasSubstr("more than 64 bits"));
    EXPECT_THAT(invalid_argument_message([&] { b.abs_diff_const("d", w48, bottom); }), HasSubstr("more than 64 bits"));
    EXPECT_THAT(invalid_argument_message([&] { b.abs_diff_const("d", b.set_const("zero", 0), bottom); }),
                HasSubstr("more than 64 bits"));  // |0 - min| is not an int64
}

TEST(PpBuilder, RejectsReleasedUnknownAndForeignFields) {
    PpProgramBuilder b("fields", 208);
    const PpField a = b.load("a", 0, 8, false);
    const PpField c = b.load("c", 8, 8, false);
    b.release(a);
    EXPECT_THAT(invalid_argument_message([&] { b.add("s", a, c); }),
                HasSubstr("field a (id 0) used after it was released"));
    EXPECT_THROW(b.release(a), std::invalid_argument);
    EXPECT_THROW(b.store(a, 0), std::invalid_argument);
    EXPECT_THROW(b.enable_if(a, PpCompare::Equal, 0), std::invalid_argument);
    EXPECT_THROW(b.assign(c, a), std::invalid_argument);
    EXPECT_THAT(invalid_argument_message([&] { b.move("m", PpField{}); }), HasSubstr("field id -1 is not a field"));
    EXPECT_THROW(b.move("m", PpField{7, 0, 8, false}), std::invalid_argument);
    // A field of another program with the same id but a different shape.
    PpProgramBuilder other("other", 208);
    other.load("x", 0, 8, false);
    const PpField foreign = other.load("y", 0, 12, true);
    EXPECT_THAT(invalid_argument_message([&] { b.move("m", foreign); }), HasSubstr("does not match"));
}

TEST(PpBuilder, RejectsBadShifts) {
    PpProgramBuilder b("shifts", 208);
    const PpField u8 = b.load("u8", 0, 8, false);
    EXPECT_THAT(invalid_argument_message([&] { b.move("m", u8, -1); }), HasSubstr("shift of -1"));
    EXPECT_THROW(b.move("m", u8, 64), std::invalid_argument);
    EXPECT_THROW(b.mul("m", u8, u8, -2), std::invalid_argument);
    EXPECT_THROW(b.mul_const("m", u8, 3, -1), std::invalid_argument);
    EXPECT_THROW(b.qee("q", 0, 8, false, -1), std::invalid_argument);
    EXPECT_THROW(b.div("d", u8, u8, -1, 8), std::invalid_argument);
    // The dividend a << shift must fit 63 bits: 255 << 56 does not; 255 << 55 does.
    EXPECT_THAT(invalid_argument_message([&] { b.div("d", u8, u8, 56, 8); }), HasSubstr("does not fit 63 bits"));
    EXPECT_EQ(b.div("d", u8, u8, 55, 8).bits, 8);
    EXPECT_EQ(b.move("m", u8, 63).bits, 1);  // [0, 0]
}

TEST(PpBuilder, DivideNeedsNonNegativeOperands) {
    PpProgramBuilder b("divide", 208);
    const PpField s8 = b.load("s8", 0, 8, true);
    const PpField u8 = b.load("u8", 8, 8, false);
    EXPECT_THAT(invalid_argument_message([&] { b.div("q", s8, u8, 0, 8); }), HasSubstr("may be negative"));
    EXPECT_THROW(b.div("q", u8, s8, 0, 8), std::invalid_argument);
    // A signed field whose range is known to be non-negative is fine.
    const PpField positive = b.max_const("positive", s8, 1);
    EXPECT_EQ(b.div("q", u8, positive, 2, 10).bits, 10);
}

TEST(PpBuilder, LookupNeedsAnUnsignedIndexAndAFullTableThatFits) {
    PpProgramBuilder b("lookup", 208);
    const PpField u4 = b.load("u4", 0, 4, false);
    const PpField s4 = b.load("s4", 4, 4, true);
    const PpTable sixteen{"sixteen", std::vector<std::int64_t>(16, 1)};
    EXPECT_THAT(invalid_argument_message([&] { b.lookup("r", s4, sixteen, 4, false); }),
                HasSubstr("indexed by signed field s4"));
    EXPECT_THAT(invalid_argument_message([&] {
                    b.lookup("r", u4, PpTable{"short", std::vector<std::int64_t>(15, 1)}, 4, false);
                }),
                HasSubstr("has 15 entries; a 4-bit index needs 2^4"));
    PpTable big = sixteen;
    big.entries[9] = 16;
    EXPECT_THAT(invalid_argument_message([&] { b.lookup("r", u4, big, 4, false); }),
                HasSubstr("entry 9 = 16 does not fit r"));
    PpTable negative = sixteen;
    negative.entries[3] = -1;
    EXPECT_THROW(b.lookup("r", u4, negative, 4, false), std::invalid_argument);
    EXPECT_EQ(b.lookup("r", u4, negative, 4, true).bits, 4);
    const PpProgram p = b.finish();
    ASSERT_EQ(p.tables.size(), 1u);
    EXPECT_EQ(p.tables[0].name, "sixteen");
    EXPECT_EQ(p.instructions.back().table, 0);
}

TEST(PpTable, RunsCountsMaximalRunsOfEqualEntries) {
    EXPECT_EQ((PpTable{"empty", {}}).runs(), 0);
    EXPECT_EQ((PpTable{"one", {5}}).runs(), 1);
    EXPECT_EQ((PpTable{"flat", {2, 2, 2, 2}}).runs(), 1);
    EXPECT_EQ((PpTable{"steps", {1, 1, 2, 2, 1}}).runs(), 3);
    EXPECT_EQ((PpTable{"all different", {0, 1, 2, 3}}).runs(), 4);
}

TEST(PpBuilder, EveryOperationHasAName) {
    std::set<std::string> names;
    for (int op = 0; op <= static_cast<int>(PpOp::Store); ++op) {
        const std::string name = to_string(static_cast<PpOp>(op));
        EXPECT_NE(name, "?");
        names.insert(name);
    }
    EXPECT_EQ(names.size(), static_cast<std::size_t>(PpOp::Store) + 1);  // all different
    EXPECT_EQ(to_string(PpOp::MulConst), "mul-const");
}

TEST(PpLocalMemory, FirstFitReusesReleasedBitsAndTracksThePeak) {
    PpProgramBuilder b("first-fit", 64);
    const PpField a = b.alloc("a", 16, false);
    const PpField c = b.alloc("c", 16, false);
    const PpField d = b.alloc("d", 16, false);
    EXPECT_EQ(a.offset, 0);
    EXPECT_EQ(c.offset, 16);
    EXPECT_EQ(d.offset, 32);
    b.release(c);
    EXPECT_EQ(b.alloc("e", 8, false).offset, 16);   // into the hole
    EXPECT_EQ(b.alloc("f", 10, false).offset, 48);  // the hole's rest (8 bits) is too small
    EXPECT_EQ(b.alloc("g", 8, false).offset, 24);
    b.release(a);
    b.release(d);
    EXPECT_EQ(b.alloc("h", 4, false).offset, 0);
    // The peak of simultaneously allocated bits, not the current use: 16 + 8 + 16 + 10 + 8 = 58.
    EXPECT_EQ(b.finish().local_memory_bits_used, 58);
}

TEST(PpLocalMemory, AProgramOneBitOverSaysSoNamingFieldAndKey) {
    PpProgramBuilder b("big", 208);
    for (int i = 0; i < 4; ++i) b.load("record", i * 48, 48, false);
    b.alloc("rest", 16, false);  // 208
    try {
        b.set_const("flag", 1);
        FAIL() << "209 bits do not fit in 208";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(),
                  "");  // the run's configuration names where the value came from (MachineConfig::naming_origin)
        EXPECT_EQ(e.field(), "renderer.local_memory_bits");
        EXPECT_EQ(e.reason(),
                  "PP program big needs 209 bits of local memory for field flag; each PP has 208 (1 bit short)");
    }
    // Another key, and a larger shortfall.
    PpProgramBuilder small("small", 40, "machine.pp_bits");
    small.alloc("x", 30, false);
    try {
        small.alloc("y", 20, true);
        FAIL() << "50 bits do not fit in 40";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "machine.pp_bits");
        EXPECT_THAT(e.reason(), HasSubstr("needs 50 bits of local memory for field y; each PP has 40 (10 bits short)"));
    }
}

TEST(PpLocalMemory, FreeBitsInPiecesSayWhyTheyDoNotFit) {
    PpProgramBuilder b("pieces", 64);
    std::vector<PpField> f;
    for (int i = 0; i < 8; ++i) f.push_back(b.alloc("f", 8, false));
    b.release(f[1]);
    b.release(f[3]);
    b.release(f[5]);
    try {
        b.alloc("wide", 12, false);  // 24 bits free, 8 at most together
        FAIL() << "no 12 contiguous bits";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "renderer.local_memory_bits");
        EXPECT_EQ(e.reason(),
                  "PP program pieces needs 12 contiguous bits of local memory for field wide; each PP has 64, "
                  "24 of them free but the longest free run is 8 bits (4 bits short)");
    }
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// A value stored into a wider record field fills all of it: an earlier value's high bits do not
// stay behind (they once did, when a narrow colour replaced a brighter one).
TEST(PpBuilder, StoreIntoARecordFieldFillsEveryBit) {
    PpProgramBuilder b("store", 208);
    const PpField three = b.set_const("three", 3);  // 2 bits
    b.store(three, 8, 8);
    const PpField wide = b.set_const("wide", 300);  // 9 bits
    EXPECT_THROW(b.store(wide, 16, 8), std::invalid_argument);
    const PpField negative = b.set_const("negative", -1);
    EXPECT_THROW(b.store(negative, 16, 8), std::invalid_argument);
    const PpProgram program = b.finish();

    PpArray array(4, 1, 208, 64);
    for (int pp = 0; pp < 4; ++pp) array.write_backing(pp, 0, 24, 0xFFFFFF);
    array.run(program, PpSlotContext{});
    for (int pp = 0; pp < 4; ++pp) {
        EXPECT_EQ(array.read_backing(pp, 8, 8), 3u);
        EXPECT_EQ(array.read_backing(pp, 0, 8), 0xFFu);  // its neighbours untouched
        EXPECT_EQ(array.read_backing(pp, 16, 8), 0xFFu);
    }
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// A long program whose temporaries are released as it goes (a classification of many contours) keeps
// only as many fields on the host as are alive at once, and computes what one field each would.
TEST(PpBuilder, ReleasedFieldsShareHostStorage) {
    constexpr int kSteps = 500;
    PpProgramBuilder b("long", 208);
    const PpField x = b.load("x", 0, 8, false);
    PpField total = b.set_const("total", 0, 20, false);
    for (int k = 0; k < kSteps; ++k) {
        const PpField term = b.add_const("term", x, k % 7);  // alive for one step only
        const PpField next = b.add("next", total, term);
        b.release(term);
        b.release(total);
        total = b.move("total", next);
        b.release(next);
    }
    const PpProgram p = b.finish();
    EXPECT_GT(p.fields.size(), static_cast<std::size_t>(3 * kSteps));
    EXPECT_LE(p.storage_slots, 4);  // x, total, and the two alive within a step

    PpArray array(4, 2, 208, 64);
    for (int pp = 0; pp < array.size(); ++pp) array.write_backing(pp, 0, 8, static_cast<std::uint64_t>(pp * 3));
    array.run(p, PpSlotContext{});
    const auto values = array.field_values(total);
    std::int64_t step_sum = 0;
    for (int k = 0; k < kSteps; ++k) step_sum += k % 7;
    for (int pp = 0; pp < array.size(); ++pp)
        EXPECT_EQ(values[static_cast<std::size_t>(pp)], kSteps * pp * 3 + step_sum) << pp;
}

}  // namespace
}  // namespace pp5
