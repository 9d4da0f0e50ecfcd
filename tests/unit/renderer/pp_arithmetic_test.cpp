// Every fixed-point operation of the PPs against an integer reference over its whole input range:
// all pairs of 8-bit operands (signed and unsigned), every input of the one-operand forms.

#include "tests/unit/renderer/pp_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace pp5 {
namespace {

using test::Operands;
using test::run_exhaustive;

enum class Width { Tight, Declared };

// Checks `body`'s result for every (a, b) against `expected`. With Width::Tight, also checks that the
// builder gave the result the narrowest field that holds every value it took (signed only if one
// was negative): the inferred widths neither overflow nor waste bits.
template <class Body, class Expected>
void check_pairs(int a_bits, bool a_signed, int b_bits, bool b_signed, Body body, Expected expected,
                 Width width = Width::Tight) {
    PpProgram program;
    const auto values = run_exhaustive(a_bits, a_signed, b_bits, b_signed, body, &program);
    const std::int64_t count_a = std::int64_t{1} << a_bits;
    const std::int64_t count_b = b_bits > 0 ? std::int64_t{1} << b_bits : 1;
    const std::int64_t a_min = a_signed ? -(count_a / 2) : 0;
    const std::int64_t b_min = b_signed ? -(count_b / 2) : 0;
    int failures = 0;
    std::int64_t lowest = std::numeric_limits<std::int64_t>::max();
    std::int64_t highest = std::numeric_limits<std::int64_t>::min();
    for (std::int64_t p = 0; p < count_a * count_b; ++p) {
        const std::int64_t a = a_min + p % count_a;
        const std::int64_t b = b_min + p / count_a;
        const std::int64_t want = expected(a, b);
        lowest = std::min(lowest, want);
        highest = std::max(highest, want);
        if (values[static_cast<std::size_t>(p)] != want && failures < 5) {
            ADD_FAILURE() << "a=" << a << " b=" << b << ": got " << values[static_cast<std::size_t>(p)] << ", want "
                          << want;
            ++failures;
        }
    }
    if (width == Width::Tight) {
        const PpField& result = program.fields[static_cast<std::size_t>(program.instructions.back().dst)];
        EXPECT_EQ(result.bits, pp_bits_for_range(lowest, highest)) << "values in [" << lowest << ", " << highest << "]";
        EXPECT_EQ(result.is_signed, lowest < 0) << "values in [" << lowest << ", " << highest << "]";
    }
}

TEST(PpArithmetic, AddAndSubtractAllEightBitPairs) {
    for (bool is_signed : {false, true}) {
        check_pairs(
            8, is_signed, 8, is_signed, [](PpProgramBuilder& b, Operands o) { return b.add("sum", o.a, o.b); },
            [](std::int64_t a, std::int64_t b) { return a + b; });
        check_pairs(
            8, is_signed, 8, is_signed, [](PpProgramBuilder& b, Operands o) { return b.sub("difference", o.a, o.b); },
            [](std::int64_t a, std::int64_t b) { return a - b; });
    }
}

TEST(PpArithmetic, MixedSignednessAllEightBitPairs) {
    // A signed and an unsigned operand: the result's range, and so its width, comes from both.
    check_pairs(
        8, true, 8, false, [](PpProgramBuilder& b, Operands o) { return b.add("sum", o.a, o.b); },
        [](std::int64_t a, std::int64_t b) { return a + b; });
    check_pairs(
        8, false, 8, true, [](PpProgramBuilder& b, Operands o) { return b.sub("difference", o.a, o.b); },
        [](std::int64_t a, std::int64_t b) { return a - b; });
    check_pairs(
        8, true, 8, false, [](PpProgramBuilder& b, Operands o) { return b.mul("product", o.a, o.b, 5); },
        [](std::int64_t a, std::int64_t b) { return (a * b) >> 5; });
    // Unequal widths: 8-bit a, 6-bit b.
    check_pairs(
        8, true, 6, true, [](PpProgramBuilder& b, Operands o) { return b.mul("product", o.a, o.b); },
        [](std::int64_t a, std::int64_t b) { return a * b; });
}

TEST(PpArithmetic, SquaresOfEveryEightBitValue) {
    // mul(a, a) knows a square is never negative: unsigned, one bit narrower than a general product.
    for (bool is_signed : {false, true}) {
        check_pairs(
            8, is_signed, 0, false, [](PpProgramBuilder& b, Operands o) { return b.mul("square", o.a, o.a); },
            [](std::int64_t a, std::int64_t) { return a * a; });
    }
}

TEST(PpArithmetic, MultiplyAllEightBitPairsWithAndWithoutShift) {
    for (bool is_signed : {false, true}) {
        for (int shift : {0, 3, 8}) {
            check_pairs(
                8, is_signed, 8, is_signed,
                [&](PpProgramBuilder& b, Operands o) { return b.mul("product", o.a, o.b, shift); },
                [&](std::int64_t a, std::int64_t b) { return (a * b) >> shift; });
        }
    }
}

TEST(PpArithmetic, DivideAllEightBitPairsSaturating) {
    // (a << 4) / b into 9 bits: saturates at 511 for b = 0 and for quotients that do not fit.
    check_pairs(
        8, false, 8, false, [](PpProgramBuilder& b, Operands o) { return b.div("quotient", o.a, o.b, 4, 9); },
        [](std::int64_t a, std::int64_t b) { return b == 0 ? 511 : std::min<std::int64_t>((a << 4) / b, 511); },
        Width::Declared);
    // Without a shift, into 8 bits: only b = 0 saturates.
    check_pairs(
        8, false, 8, false, [](PpProgramBuilder& b, Operands o) { return b.div("quotient", o.a, o.b, 0, 8); },
        [](std::int64_t a, std::int64_t b) { return b == 0 ? 255 : a / b; }, Width::Declared);
}

TEST(PpArithmetic, ConstantFormsOverEveryInput) {
    for (bool is_signed : {false, true}) {
        for (std::int64_t k : {-300, -128, -7, -1, 0, 1, 5, 100, 127, 255}) {
            check_pairs(
                8, is_signed, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.add_const("r", o.a, k); },
                [&](std::int64_t a, std::int64_t) { return a + k; });
            check_pairs(
                8, is_signed, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.abs_diff_const("r", o.a, k); },
                [&](std::int64_t a, std::int64_t) { return std::abs(a - k); });
            check_pairs(
                8, is_signed, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.min_const("r", o.a, k); },
                [&](std::int64_t a, std::int64_t) { return std::min(a, k); });
            check_pairs(
                8, is_signed, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.max_const("r", o.a, k); },
                [&](std::int64_t a, std::int64_t) { return std::max(a, k); });
            check_pairs(
                8, is_signed, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.mul_const("r", o.a, k, 2); },
                [&](std::int64_t a, std::int64_t) { return (a * k) >> 2; });
            check_pairs(
                8, is_signed, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.move("r", o.a, 3); },
                [&](std::int64_t a, std::int64_t) { return a >> 3; });
        }
    }
}

TEST(PpArithmetic, SquareRootOfEverySixteenBitValue) {
    check_pairs(
        16, false, 0, false, [](PpProgramBuilder& b, Operands o) { return b.sqrt("root", o.a); },
        [](std::int64_t a, std::int64_t) {
            std::int64_t r = 0;
            while ((r + 1) * (r + 1) <= a) ++r;
            return r;
        });
    // A signed operand: negative values give 0 (the root's range starts at 0, so it is unsigned).
    check_pairs(
        16, true, 0, false, [](PpProgramBuilder& b, Operands o) { return b.sqrt("root", o.a); },
        [](std::int64_t a, std::int64_t) {
            std::int64_t r = 0;
            while ((r + 1) * (r + 1) <= a) ++r;
            return r;
        });
}

// The widest operands a field may hold, where a square root in double precision is no longer
// exact by itself: perfect squares, one below and one above, up to 2^48 - 1.
TEST(PpArithmetic, SquareRootOfWideValuesAroundPerfectSquares) {
    std::vector<std::int64_t> inputs = {0, 1, 2, 3, (std::int64_t{1} << 48) - 1};
    for (std::int64_t root = 2; root < (std::int64_t{1} << 24); root = root * 3 / 2 + 1)
        for (std::int64_t d : {-1, 0, 1}) inputs.push_back(root * root + d);
    for (std::int64_t root : {(std::int64_t{1} << 24) - 1, (std::int64_t{1} << 24) - 2})
        for (std::int64_t d : {-1, 0, 1}) inputs.push_back(root * root + d);
    PpArray array(static_cast<int>(inputs.size()), 1, 208, 64);
    for (std::size_t p = 0; p < inputs.size(); ++p)
        array.write_backing(static_cast<int>(p), 0, 48, static_cast<std::uint64_t>(inputs[p]));
    PpProgramBuilder b("wide roots", 208);
    const PpField root = b.sqrt("root", b.load("a", 0, 48, false));
    array.run(b.finish(), PpSlotContext{});
    const auto roots = array.field_values(root);
    for (std::size_t p = 0; p < inputs.size(); ++p) {
        const std::int64_t r = roots[p];
        EXPECT_TRUE(r >= 0 && r * r <= inputs[p] && (r + 1) * (r + 1) > inputs[p])
            << "sqrt(" << inputs[p] << ") gave " << r;
    }
}

TEST(PpArithmetic, LookupOfEveryIndex) {
    PpTable table{"squares", {}};
    for (int i = 0; i < 256; ++i) table.entries.push_back((i * i) % 1000 - 500);
    check_pairs(
        8, false, 0, false, [&](PpProgramBuilder& b, Operands o) { return b.lookup("r", o.a, table, 10, true); },
        [&](std::int64_t a, std::int64_t) { return table.entries[static_cast<std::size_t>(a)]; }, Width::Declared);
}

TEST(PpArithmetic, QeeGivesEachPpItsOwnValue) {
    PpArray array(7, 5, 208, 64);
    PpProgramBuilder b("qee", 208);
    const PpField q = b.qee("q", 0, 16, true, 2);
    const PpProgram program = b.finish();
    const QeeCoefficients e{3, -2, 1, 5, -7, 40};
    array.run(program, PpSlotContext{0, std::span<const QeeCoefficients>(&e, 1)});
    const auto values = array.field_values(q);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x)
            EXPECT_EQ(values[static_cast<std::size_t>(x + 7 * y)],
                      (3 * x * x - 2 * x * y + y * y + 5 * x - 7 * y + 40) >> 2);
}

TEST(PpArithmetic, DisabledPpsKeepTheirValues) {
    PpArray array(16, 1, 208, 64);
    for (int p = 0; p < 16; ++p) array.write_backing(p, 0, 8, static_cast<std::uint64_t>(p));
    PpProgramBuilder b("masked", 208);
    const PpField v = b.load("v", 0, 8, false);
    const PpField r = b.set_const("r", 99, 8, false);
    b.enable_if(v, PpCompare::GreaterEqual, 10);
    b.assign(r, v);
    b.enable_all();
    const PpProgram program = b.finish();
    const PpRunCounts counts = array.run(program, PpSlotContext{});
    const auto values = array.field_values(r);
    for (int p = 0; p < 16; ++p) EXPECT_EQ(values[static_cast<std::size_t>(p)], p >= 10 ? p : 99);
    EXPECT_EQ(counts.instructions, 5u);
    EXPECT_EQ(counts.pp_operations, 5u * 16u);
    // load, set and enable-if on all 16; the move on the 6 enabled; enable-all on 6 (counted before).
    EXPECT_EQ(counts.enabled_pp_operations, 16u * 3u + 6u + 6u);
}

TEST(PpArithmetic, WidthsFollowTheValueRanges) {
    PpProgramBuilder b("widths", 208);
    const PpField gx = b.load("gx", 0, 8, true);
    const PpField gy = b.load("gy", 8, 8, true);
    const PpField gz = b.load("gz", 16, 8, true);
    const PpField sum = b.add("s", b.add("s2", b.mul("x2", gx, gx), b.mul("y2", gy, gy)), b.mul("z2", gz, gz));
    EXPECT_FALSE(sum.is_signed);
    EXPECT_EQ(sum.bits, 16);                  // 3 * 128^2 = 49152 < 2^16
    EXPECT_EQ(b.sqrt("m", sum).bits, 8);      // 221
    EXPECT_EQ(b.mul("xy", gx, gy).bits, 16);  // [-16256, 16384]: signed
    EXPECT_EQ(pp_bits_for_range(-128, 127), 8);
    EXPECT_EQ(pp_bits_for_range(0, 256), 9);
}

}  // namespace
}  // namespace pp5
