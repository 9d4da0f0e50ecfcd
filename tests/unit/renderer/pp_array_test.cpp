// The PP array's execution: loads sign-extend and stores write only their bits, every result wraps
// to its field's width, every operation's writes (and stores) are masked by the enable bit, the QEE
// gives each PP its own value across the array's blocks, counts are exact, and a program the array
// cannot run is refused before anything changes; programs run in 32-bit lanes leave what they leave in
// 64-bit ones. Also the backing store against a bit-by-bit model.

#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_field_store.h"
#include "sim/pixel_processors/pp_program.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace pp5 {
namespace {

// A value as a field of `bits` bits holds it: modulo 2^bits, two's complement when signed.
std::int64_t wrapped(std::int64_t v, int bits, bool is_signed) {
    const auto mask = (std::uint64_t{1} << bits) - 1;
    auto u = static_cast<std::uint64_t>(v) & mask;
    if (is_signed && (u >> (bits - 1)) != 0) u |= ~mask;
    return static_cast<std::int64_t>(u);
}

std::span<const QeeCoefficients> one(const QeeCoefficients& q) { return {&q, 1}; }

TEST(PpFieldStore, SlotsStartOnDifferentLinesOfAPageAndKeepTheirValuesAsTheStoreGrows) {
    PpFieldStore<std::int32_t> store(16384);
    store.reserve(3);
    for (std::size_t s = 0; s < 3; ++s)
        for (std::size_t i = 0; i < store.lanes(); ++i) store.slot(s)[i] = static_cast<std::int32_t>(s * 100000 + i);
    store.reserve(64);
    EXPECT_EQ(store.slots(), 64u);
    std::set<std::uintptr_t> lines;  // each slot's first cache line within its 4 KB page
    for (std::size_t s = 0; s < store.slots(); ++s) {
        const auto start = reinterpret_cast<std::uintptr_t>(store.slot(s));
        EXPECT_EQ(start % 64, 0u) << s;
        lines.insert(start % 4096 / 64);
        if (s > 0) {
            EXPECT_GE(start, reinterpret_cast<std::uintptr_t>(store.slot(s - 1) + store.lanes())) << s;
        }
        for (std::size_t i = 0; i < store.lanes(); i += 1000)
            ASSERT_EQ(store.slot(s)[i], s < 3 ? static_cast<std::int32_t>(s * 100000 + i) : 0) << s << " " << i;
    }
    EXPECT_EQ(lines.size(), 64u);
}

TEST(PpArray, ConstructorRejectsNonPositiveSizes) {
    EXPECT_THROW(PpArray(0, 4, 208, 64), std::invalid_argument);
    EXPECT_THROW(PpArray(4, 0, 208, 64), std::invalid_argument);
    EXPECT_THROW(PpArray(4, 4, 0, 64), std::invalid_argument);
    EXPECT_THROW(PpArray(4, 4, 208, -1), std::invalid_argument);
    const PpArray no_backing(3, 2, 208, 0);  // a backing store is optional
    EXPECT_EQ(no_backing.size(), 6);
    EXPECT_THROW(no_backing.read_backing(0, 0, 1), std::out_of_range);
}

TEST(PpBackingStore, RandomWritesMatchABitByBitModel) {
    // Widths 1..64 at any offset, straddling words, against one bool per bit.
    constexpr int kBits = 300;
    PpArray array(3, 2, 208, kBits);
    std::vector<std::vector<bool>> model(6, std::vector<bool>(kBits, false));
    std::mt19937_64 rng(7);
    for (int step = 0; step < 3000; ++step) {
        const int pp = static_cast<int>(rng() % 6);
        const int bits = 1 + static_cast<int>(rng() % 64);
        const int offset = static_cast<int>(rng() % static_cast<std::uint64_t>(kBits - bits + 1));
        const std::uint64_t value = rng();  // bits past `bits` must be ignored
        array.write_backing(pp, offset, bits, value);
        for (int i = 0; i < bits; ++i) {
            model[static_cast<std::size_t>(pp)][static_cast<std::size_t>(offset + i)] = ((value >> i) & 1) != 0;
        }
        const int read_bits = 1 + static_cast<int>(rng() % 64);
        const int read_offset = static_cast<int>(rng() % static_cast<std::uint64_t>(kBits - read_bits + 1));
        const int read_pp = static_cast<int>(rng() % 6);
        std::uint64_t want = 0;
        for (int i = 0; i < read_bits; ++i) {
            if (model[static_cast<std::size_t>(read_pp)][static_cast<std::size_t>(read_offset + i)])
                want |= std::uint64_t{1} << i;
        }
        ASSERT_EQ(array.read_backing(read_pp, read_offset, read_bits), want)
            << "step " << step << ": PP " << read_pp << ", " << read_bits << " bits at " << read_offset;
    }
}

TEST(PpBackingStore, AccessOutsideTheStoreThrows) {
    PpArray array(2, 2, 208, 128);
    EXPECT_NO_THROW(array.write_backing(3, 64, 64, ~0ull));
    EXPECT_EQ(array.read_backing(3, 64, 64), ~0ull);
    EXPECT_THROW(array.write_backing(3, 65, 64, 0), std::out_of_range);  // one bit past the end
    EXPECT_THROW(array.read_backing(0, 127, 2), std::out_of_range);
    EXPECT_THROW(array.read_backing(0, -1, 8), std::out_of_range);
    EXPECT_THROW(array.read_backing(0, 0, 0), std::out_of_range);
    EXPECT_THROW(array.read_backing(0, 0, 65), std::out_of_range);
    EXPECT_THROW(array.read_backing(-1, 0, 8), std::out_of_range);
    EXPECT_THROW(array.write_backing(4, 0, 8, 0), std::out_of_range);
    EXPECT_THROW(array.read_backing(0, 2147483600, 64), std::out_of_range);  // no overflow in the check
}

TEST(PpBackingStore, ARunOfPpsReadsAsEachDoesAndIsCheckedWhole) {
    PpArray array(4, 3, 64, 192);
    std::mt19937_64 random(9);
    for (int pp = 0; pp < array.size(); ++pp) array.write_backing(pp, 50, 40, random());  // straddles two words
    const PpBackingReader reader = array.backing_reader(50, 40);
    std::vector<std::uint64_t> run(5);
    reader.read_run(6, run);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(run[static_cast<std::size_t>(i)], array.read_backing(6 + i, 50, 40)) << i;
    EXPECT_THROW(reader.read_run(8, run), std::out_of_range);  // its last PP is past the array
    EXPECT_THROW(reader.read_run(-1, run), std::out_of_range);
    EXPECT_NO_THROW(reader.read_run(12, std::span<std::uint64_t>()));  // an empty run reads nothing
}

TEST(PpArray, LoadsSignExtendAndStoresWriteOnlyTheirBits) {
    PpArray array(4, 1, 208, 256);
    const std::int64_t inputs[4] = {0, 1, 127, 255};
    for (int p = 0; p < 4; ++p) {
        array.write_backing(p, 60, 8, static_cast<std::uint64_t>(inputs[p]));  // straddles words 0 and 1
        array.write_backing(p, 130, 30, (1u << 30) - 1);                       // ones around the store
    }
    PpProgramBuilder b("io", 208);
    const PpField s = b.load("s", 20, 8, true);
    const PpField u = b.load("u", 20, 8, false);
    const PpField y = b.add_const("y", s, -3);  // 9 bits signed
    b.store(y, 100);
    const PpProgram program = b.finish();
    array.run(program, PpSlotContext{40, {}});  // the record starts at bit 40: loads from 60, stores at 140
    for (int p = 0; p < 4; ++p) {
        const std::int64_t as_signed = inputs[p] >= 128 ? inputs[p] - 256 : inputs[p];
        EXPECT_EQ(array.field_values(s)[static_cast<std::size_t>(p)], as_signed);
        EXPECT_EQ(array.field_values(u)[static_cast<std::size_t>(p)], inputs[p]);
        EXPECT_EQ(array.read_backing(p, 140, 9), static_cast<std::uint64_t>(as_signed - 3) & 0x1FF);
        EXPECT_EQ(array.read_backing(p, 130, 10), 0x3FFu);  // below the store
        EXPECT_EQ(array.read_backing(p, 149, 11), 0x7FFu);  // above it
    }
}

TEST(PpArray, EveryResultWrapsToItsFieldsWidth) {
    // A program made by hand, with fields narrower than their results: the array keeps what
    // bit-serial hardware would keep (the builder never makes such a program, except by QEE).
    PpProgram p;
    p.name = "narrow";
    p.fields = {PpField{0, 0, 8, false, 0},  PpField{1, 8, 4, true, 1},  PpField{2, 12, 4, false, 2},
                PpField{3, 16, 8, false, 3}, PpField{4, 24, 3, true, 4}, PpField{5, 27, 5, false, 5},
                PpField{6, 32, 6, true, 6}};
    p.storage_slots = 7;
    p.field_names = {"a", "twice", "next", "k", "lut", "prod", "neg"};
    p.tables = {PpTable{"wide", {}}};
    for (int i = 0; i < 256; ++i) p.tables[0].entries.push_back(i * 3 - 300);
    auto op = [](PpOp o, int dst, int a, int b, std::int64_t imm) {
        PpInstruction in{o};
        in.dst = dst;
        in.a = a;
        in.b = b;
        in.imm = imm;
        return in;
    };
    p.instructions = {op(PpOp::Load, 0, -1, -1, 0),    op(PpOp::Add, 1, 0, 0, 0),
                      op(PpOp::AddConst, 2, 0, -1, 1), op(PpOp::SetConst, 3, -1, -1, 300),
                      op(PpOp::Lookup, 4, 0, -1, 0),   op(PpOp::MulConst, 5, 0, -1, 7),
                      op(PpOp::Sub, 6, 3, 0, 0)};
    p.instructions[4].table = 0;
    p.local_memory_bits_used = 38;

    PpArray array(16, 16, 208, 64);
    for (int v = 0; v < 256; ++v) array.write_backing(v, 0, 8, static_cast<std::uint64_t>(v));
    array.run(p, PpSlotContext{});
    for (int v = 0; v < 256; ++v) {
        const auto at = [&](int id) {
            return array.field_values(p.fields[static_cast<std::size_t>(id)])[static_cast<std::size_t>(v)];
        };
        ASSERT_EQ(at(1), wrapped(2 * v, 4, true)) << v;
        ASSERT_EQ(at(2), wrapped(v + 1, 4, false)) << v;
        ASSERT_EQ(at(3), 44) << v;  // 300 mod 256
        ASSERT_EQ(at(4), wrapped(v * 3 - 300, 3, true)) << v;
        ASSERT_EQ(at(5), wrapped(v * 7, 5, false)) << v;
        ASSERT_EQ(at(6), wrapped(44 - v, 6, true)) << v;
    }
}

TEST(PpArray, QeeGivesEveryPpItsValueAcrossBlocks) {
    // 100 x 37 PPs: the array runs in blocks of PPs that end mid-row. Coefficients of both signs,
    // a shift (arithmetic: floor), a 48-bit field and a narrow one that wraps.
    PpArray array(100, 37, 208, 64);
    PpProgramBuilder b("qee", 208);
    const PpField full = b.qee("full", 0, 48, true, 3);
    const PpField narrow = b.qee("narrow", 1, 10, false, 0);
    const PpProgram program = b.finish();
    const QeeCoefficients q[2] = {{-3, 5, 2, -7, 11, -13}, {std::int64_t{1} << 40, -9, 4, 1, -1, 123456789}};
    array.run(program, PpSlotContext{0, std::span<const QeeCoefficients>(q, 2)});
    for (std::int64_t y = 0; y < 37; ++y) {
        for (std::int64_t x = 0; x < 100; ++x) {
            const auto p = static_cast<std::size_t>(x + 100 * y);
            const std::int64_t v0 = -3 * x * x + 5 * x * y + 2 * y * y - 7 * x + 11 * y - 13;
            const std::int64_t v1 = (std::int64_t{1} << 40) * x * x - 9 * x * y + 4 * y * y + x - y + 123456789;
            ASSERT_EQ(array.field_values(full)[p], v0 >> 3) << x << ", " << y;
            ASSERT_EQ(array.field_values(narrow)[p], wrapped(v1, 10, false)) << x << ", " << y;
        }
    }
}

// Inputs per PP for the masking test: a flag, two operands and a late-loaded value.
struct MaskInputs {
    std::vector<int> flag;
    std::vector<std::int64_t> a, b, late;
};

void write_inputs(PpArray& array, const MaskInputs& in) {
    for (int p = 0; p < array.size(); ++p) {
        const auto i = static_cast<std::size_t>(p);
        array.write_backing(p, 0, 1, static_cast<std::uint64_t>(in.flag[i]));
        array.write_backing(p, 8, 8, static_cast<std::uint64_t>(in.a[i]));
        array.write_backing(p, 16, 8, static_cast<std::uint64_t>(in.b[i]));
        array.write_backing(p, 24, 8, static_cast<std::uint64_t>(in.late[i]));
    }
}

MaskInputs random_inputs(int pps, std::uint32_t seed, bool all_enabled) {
    std::mt19937 rng(seed);
    MaskInputs in;
    for (int p = 0; p < pps; ++p) {
        // The first block (1024 PPs) all enabled, the rest mixed: both the plain and the blended loops.
        in.flag.push_back(all_enabled || p < 1024 ? 1 : static_cast<int>(rng() % 2));
        in.a.push_back(static_cast<std::int64_t>(rng() % 256) - 128);
        in.b.push_back(static_cast<std::int64_t>(rng() % 256));
        in.late.push_back(static_cast<std::int64_t>(rng() % 256));
    }
    return in;
}

TEST(PpArray, EveryWriteAndStoreIsMaskedByTheEnableBit) {
    // Run a program once with every PP enabled, then again with new inputs and some PPs disabled:
    // each field of a disabled PP keeps its first-run value (storage persists across runs), each
    // enabled PP gets what a run with every PP enabled would give, and the same holds for the store.
    PpProgramBuilder b("masked", 4096);
    const PpField flag = b.load("flag", 0, 1, false);
    const PpField a = b.load("a", 8, 8, true);
    const PpField bb = b.load("b", 16, 8, false);
    b.enable_if(flag, PpCompare::Equal, 1);
    std::vector<PpField> results = {
        b.load("late", 24, 8, false),
        b.add("add", a, bb),
        b.sub("sub", a, bb),
        b.add_const("add_const", a, 5),
        b.abs_diff_const("abs_diff", a, 3),
        b.min_const("min", a, 10),
        b.max_const("max", a, -10),
        b.mul("mul", a, bb, 2),
        b.mul_const("mul_const", a, -7, 1),
        b.move("move", a, 1),
        b.sqrt("sqrt", bb),
        b.lookup("lookup", bb,
                 PpTable{"t",
                         [] {
                             std::vector<std::int64_t> e;
                             for (int i = 0; i < 256; ++i) e.push_back((i * 37) % 101);
                             return e;
                         }()},
                 7, false),
        b.qee("qee", 0, 24, true, 1),
    };
    results.push_back(b.div("div", bb, results[0], 3, 10));
    const PpField copy = b.set_const("copy", 0, 10, true);  // add: [-128, 382]
    b.assign(copy, results[1]);                             // a Move into an existing field
    results.push_back(copy);
    b.store(results[1], 40);
    b.store(a, 60);  // loaded on every PP: an unmasked store would change a disabled PP's record
    b.enable_all();
    const PpProgram program = b.finish();

    const int columns = 50, rows = 45;  // 2250 PPs: three blocks
    const int pps = columns * rows;
    const QeeCoefficients q1{1, 2, 3, 4, 5, 6}, q2{-6, 5, -4, 3, -2, 1};
    const MaskInputs first = random_inputs(pps, 1, true);
    const MaskInputs second = random_inputs(pps, 2, false);

    // What the second inputs give with every PP enabled.
    PpArray reference(columns, rows, 4096, 128);
    write_inputs(reference,
                 MaskInputs{std::vector<int>(static_cast<std::size_t>(pps), 1), second.a, second.b, second.late});
    reference.run(program, PpSlotContext{0, one(q2)});

    PpArray array(columns, rows, 4096, 128);
    write_inputs(array, first);
    array.run(program, PpSlotContext{0, one(q1)});
    std::vector<std::vector<std::int64_t>> before;
    for (const PpField& f : results) before.push_back(array.field_values(f));
    std::vector<std::uint64_t> stored_before, a_stored_before;
    for (int p = 0; p < pps; ++p) {
        stored_before.push_back(array.read_backing(p, 40, results[1].bits));
        a_stored_before.push_back(array.read_backing(p, 60, 8));
    }

    write_inputs(array, second);
    const PpRunCounts counts = array.run(program, PpSlotContext{0, one(q2)});
    int enabled = 0;
    for (int p = 0; p < pps; ++p) {
        const auto i = static_cast<std::size_t>(p);
        const bool on = second.flag[i] == 1;
        enabled += on ? 1 : 0;
        for (std::size_t r = 0; r < results.size(); ++r) {
            const std::int64_t want = on ? reference.field_values(results[r])[i] : before[r][i];
            ASSERT_EQ(array.field_values(results[r])[i], want)
                << program.field_names[static_cast<std::size_t>(results[r].id)] << " at PP " << p
                << (on ? " (enabled)" : " (disabled)");
        }
        const std::uint64_t stored = on ? reference.read_backing(p, 40, results[1].bits) : stored_before[i];
        ASSERT_EQ(array.read_backing(p, 40, results[1].bits), stored) << "store at PP " << p;
        const std::uint64_t a_stored = on ? static_cast<std::uint64_t>(second.a[i]) & 0xFF : a_stored_before[i];
        ASSERT_EQ(array.read_backing(p, 60, 8), a_stored) << "store of a at PP " << p;
    }
    ASSERT_GT(enabled, 1024);
    ASSERT_LT(enabled, pps);
    // 3 loads and the enable-if on every PP; the masked instructions and the enable-all on the enabled.
    const auto n = static_cast<std::uint64_t>(program.instructions.size());
    EXPECT_EQ(counts.instructions, n);
    EXPECT_EQ(counts.pp_operations, n * static_cast<std::uint64_t>(pps));
    EXPECT_EQ(counts.enabled_pp_operations,
              4u * static_cast<std::uint64_t>(pps) + (n - 4u) * static_cast<std::uint64_t>(enabled));
    EXPECT_NE(first.a, second.a);
}

// A program of two tested groups: PPs near the line x = 2 y, then PPs right of x = 85.
struct TwoGroupProgram {
    PpProgram program;
    std::vector<QeeCoefficients> expressions{{0, 0, 0, 1, -2, 0}, {0, 0, 0, 1, 0, -85}};

    // Whether a PP fails the first test of both groups.
    static bool bystander(int x, int y) { return std::abs(x - 2 * y) > 12 && x - 85 <= 0; }

    TwoGroupProgram() {
        PpProgramBuilder b("two groups", 208);
        const PpField sum = b.set_const("sum", 0, 16, true);
        b.enable_all();
        const PpField v = b.qee("line", 0, 16, true, 0);
        const PpField near = b.abs_diff_const("|line|", v, 0);
        b.enable_if(near, PpCompare::LessEqual, 12);
        const PpField a = b.load("a", 8, 8, true);
        b.enable_if(a, PpCompare::GreaterEqual, 0);
        b.assign(sum, b.add_const("a + 1", a, 1));
        b.store(sum, 32);
        b.enable_all();
        const PpField w = b.qee("right", 1, 12, true, 0);
        b.enable_if(w, PpCompare::Greater, 0);
        b.store(b.mul_const("w x 3", w, 3), 48);
        b.enable_all();
        program = b.finish();
    }
};

void write_random_store(PpArray& array, std::uint32_t seed) {
    std::mt19937_64 rng(seed);
    for (int p = 0; p < array.size(); ++p) array.write_backing(p, 0, 64, rng());
}

TEST(PpArray, CandidatesAloneLeaveWhatTheWholeRunLeavesAndCountTheSame) {
    // 100 x 37 PPs, so the candidates span more than one block; and a superset of them, which may
    // include bystanders.
    const TwoGroupProgram two;
    std::vector<int> exact, superset;
    for (int p = 0; p < 100 * 37; ++p) {
        const bool candidate = !TwoGroupProgram::bystander(p % 100, p / 100);
        if (candidate) exact.push_back(p);
        if (candidate || p % 7 == 0) superset.push_back(p);
    }
    ASSERT_GT(exact.size(), 1024u);
    ASSERT_LT(exact.size(), 100u * 37u / 2);
    const PpSlotContext context{0, two.expressions};
    PpArray whole(100, 37, 208, 64);
    write_random_store(whole, 5);
    const PpRunCounts want = whole.run(two.program, context);
    for (const std::vector<int>* candidates : {&exact, &superset}) {
        PpArray listed(100, 37, 208, 64);
        write_random_store(listed, 5);
        const PpRunCounts got = listed.run_candidates(two.program, context, *candidates);
        for (int p = 0; p < 100 * 37; ++p)
            ASSERT_EQ(listed.read_backing(p, 0, 64), whole.read_backing(p, 0, 64)) << "PP " << p;
        EXPECT_EQ(got.instructions, want.instructions);
        EXPECT_EQ(got.pp_operations, want.pp_operations);
        EXPECT_EQ(got.enabled_pp_operations, want.enabled_pp_operations);
    }
    // Each group's first test rules a bystander out: the set-const and enable-all, the line's three
    // instructions, then the right's QEE and its test.
    const PpBystander bystander = bystander_of(two.program);
    EXPECT_EQ(bystander.enabled_operations, 7u);
    EXPECT_FALSE(bystander.stores);
}

TEST(PpArray, CandidateRunsRefuseWhatTheyCannotVouchFor) {
    const TwoGroupProgram two;
    const PpSlotContext context{0, two.expressions};
    PpArray array(100, 37, 208, 64);
    write_random_store(array, 9);
    const std::vector<int> descending{5, 3};
    const std::vector<int> outside{0, 100 * 37};
    EXPECT_THROW(array.run_candidates(two.program, context, descending), std::invalid_argument);
    EXPECT_THROW(array.run_candidates(two.program, context, outside), std::invalid_argument);
    // A store before any test would change bystanders too.
    PpProgramBuilder b("stores first", 208);
    b.store(b.set_const("one", 1, 8, false), 0, 8);
    const PpField one = b.load("one", 0, 8, false);
    b.enable_if(one, PpCompare::Equal, 1);
    const PpProgram stores_first = b.finish();
    EXPECT_TRUE(bystander_of(stores_first).stores);
    EXPECT_THROW(array.run_candidates(stores_first, context, std::vector<int>{0, 1}), std::invalid_argument);
    PpArray untouched(100, 37, 208, 64);
    write_random_store(untouched, 9);
    for (int p = 0; p < 100 * 37; ++p) ASSERT_EQ(array.read_backing(p, 0, 64), untouched.read_backing(p, 0, 64));
}

TEST(PpArray, CountsAddUpOverRuns) {
    PpRunCounts total;
    total += PpRunCounts{2, 20, 15};
    total += PpRunCounts{3, 30, 30};
    EXPECT_EQ(total.instructions, 5u);
    EXPECT_EQ(total.pp_operations, 50u);
    EXPECT_EQ(total.enabled_pp_operations, 45u);
}

TEST(PpArray, DivideAndSquareRootAreExactAtFullWidth) {
    // 48-bit operands: roots of k^2 - 1, k^2 and k^2 + 1 near 2^24, where a double estimate alone
    // can be off by one; quotients of 40-bit dividends shifted by 8, saturating at 2^40 - 1.
    constexpr int kPps = 512;
    PpArray array(kPps, 1, 208, 128);
    std::mt19937_64 rng(3);
    std::vector<std::int64_t> square(kPps), dividend(kPps), divisor(kPps);
    for (int p = 0; p < kPps; ++p) {
        const auto i = static_cast<std::size_t>(p);
        const std::int64_t k = (std::int64_t{1} << 24) - 1 - p / 3;
        square[i] = p % 3 == 0 ? k * k - 1 : p % 3 == 1 ? k * k : k * k + 1;
        if (p == kPps - 1) square[i] = (std::int64_t{1} << 48) - 1;
        dividend[i] = static_cast<std::int64_t>(rng() >> 24);                              // 40 bits
        divisor[i] = p % 17 == 0 ? 0 : static_cast<std::int64_t>(rng() >> (24 + p % 40));  // 40 bits down to 1
        array.write_backing(p, 0, 48, static_cast<std::uint64_t>(square[i]));
        array.write_backing(p, 48, 40, static_cast<std::uint64_t>(dividend[i]));
        array.write_backing(p, 88, 40, static_cast<std::uint64_t>(divisor[i]));
    }
    PpProgramBuilder b("wide", 208);
    const PpField s = b.load("s", 0, 48, false);
    const PpField root = b.sqrt("root", s);
    b.release(s);
    const PpField n = b.load("n", 48, 40, false);
    const PpField d = b.load("d", 88, 40, false);
    const PpField q = b.div("q", n, d, 8, 40);
    const PpProgram program = b.finish();
    array.run(program, PpSlotContext{});
    const std::int64_t top = (std::int64_t{1} << 40) - 1;
    for (int p = 0; p < kPps; ++p) {
        const auto i = static_cast<std::size_t>(p);
        const std::int64_t r = array.field_values(root)[i];
        ASSERT_TRUE(r * r <= square[i] && (r + 1) * (r + 1) > square[i]) << square[i] << " -> " << r;
        const std::int64_t want = divisor[i] == 0 ? top : std::min(top, (dividend[i] << 8) / divisor[i]);
        ASSERT_EQ(array.field_values(q)[i], want) << dividend[i] << " / " << divisor[i];
    }
}

TEST(PpArray, DividendsPastADoublesPrecisionAreDividedExactlyBesideSmallOnes) {
    // 48-bit dividends shifted by 12: some shifted values stay below 2^52, where a double holds them
    // exactly, and the rest reach 2^60, in the same blocks; every third PP is disabled and keeps the
    // value a first division left.
    constexpr int kPps = 3000;
    PpArray array(kPps, 1, 256, 96);
    std::mt19937_64 rng(11);
    std::vector<std::int64_t> dividend(kPps), divisor(kPps);
    for (int p = 0; p < kPps; ++p) {
        const auto i = static_cast<std::size_t>(p);
        dividend[i] = static_cast<std::int64_t>(rng() >> (16 + p % 33));                       // 48 bits down to 16
        divisor[i] = p % 29 == 0 ? 0 : static_cast<std::int64_t>(rng() >> (40 + p % 24)) | 1;  // 24 bits down to 1
        array.write_backing(p, 0, 48, static_cast<std::uint64_t>(dividend[i]));
        array.write_backing(p, 48, 24, static_cast<std::uint64_t>(divisor[i]));
        array.write_backing(p, 72, 2, static_cast<std::uint64_t>(p % 3 == 0 ? 0 : 1));
    }
    PpProgramBuilder b("wide_dividends", 256);
    const PpField n = b.load("n", 0, 48, false);
    const PpField d = b.load("d", 48, 24, false);
    const PpField on = b.load("on", 72, 2, false);
    const PpField q = b.set_const("q", 7, 48, false);
    b.enable_if(on, PpCompare::Equal, 1);
    const PpField quotient = b.div("quotient", n, d, 12, 48);
    b.assign(q, quotient);
    b.enable_all();
    const PpProgram program = b.finish();
    array.run(program, PpSlotContext{});
    const std::int64_t top = (std::int64_t{1} << 48) - 1;
    const auto values = array.field_values(q);
    int past_double = 0;
    for (int p = 0; p < kPps; ++p) {
        const auto i = static_cast<std::size_t>(p);
        const std::int64_t shifted = dividend[i] << 12;
        if (p % 3 != 0 && shifted >= (std::int64_t{1} << 52)) ++past_double;
        const std::int64_t want = p % 3 == 0 ? 7 : divisor[i] == 0 ? top : std::min(top, shifted / divisor[i]);
        ASSERT_EQ(values[i], want) << dividend[i] << " << 12 / " << divisor[i] << " at PP " << p;
    }
    EXPECT_GT(past_double, kPps / 10);  // the integer path ran, beside the double one
}

TEST(PpArray, ADivideOverAFewEnabledPpsDividesOnlyThemAndTheOthersKeepTheirValues) {
    // Fewer than a quarter of each block's PPs enabled, so only theirs are gathered and divided: in
    // 32-bit lanes (16-bit operands), and in 64-bit ones with some shifted dividends past 2^52 in the
    // same blocks as small ones. Every disabled PP keeps the 7 it was given.
    for (const int dividend_bits : {16, 48}) {
        SCOPED_TRACE(dividend_bits);
        constexpr int kPps = 4100;  // four whole blocks and a short one
        constexpr int kShift = 8;
        PpArray array(kPps, 1, 256, 96);
        std::mt19937_64 rng(static_cast<std::uint64_t>(dividend_bits));
        std::vector<std::int64_t> dividend(kPps), divisor(kPps);
        std::vector<bool> enabled(kPps);
        for (int p = 0; p < kPps; ++p) {
            const auto i = static_cast<std::size_t>(p);
            dividend[i] = static_cast<std::int64_t>(rng() >> (64 - dividend_bits + p % 9));
            divisor[i] = p % 23 == 0 ? 0 : static_cast<std::int64_t>(rng() >> (52 + p % 12));  // 12 bits down to 1
            enabled[i] = p % 7 == 0 || (p > 4090 && p % 2 == 0);
            array.write_backing(p, 0, 48, static_cast<std::uint64_t>(dividend[i]));
            array.write_backing(p, 48, 16, static_cast<std::uint64_t>(divisor[i]));
            array.write_backing(p, 64, 1, enabled[i] ? 1 : 0);
        }
        PpProgramBuilder b("few_dividends", 256);
        const PpField n = b.load("n", 0, dividend_bits, false);
        const PpField d = b.load("d", 48, 16, false);
        const PpField on = b.load("on", 64, 1, false);
        const PpField q = b.set_const("q", 7, dividend_bits, false);
        b.enable_if(on, PpCompare::Equal, 1);
        const PpField quotient = b.div("quotient", n, d, kShift, dividend_bits);
        b.assign(q, quotient);
        b.enable_all();
        const PpProgram program = b.finish();
        array.run(program, PpSlotContext{});
        EXPECT_EQ(array.ran_in_narrow_lanes(), dividend_bits <= 31);
        const std::int64_t top = (std::int64_t{1} << dividend_bits) - 1;
        const auto values = array.field_values(q);
        int past_double = 0;
        for (int p = 0; p < kPps; ++p) {
            const auto i = static_cast<std::size_t>(p);
            const std::int64_t shifted = dividend[i] << kShift;
            if (enabled[i] && shifted >= (std::int64_t{1} << 52)) ++past_double;
            const std::int64_t want = !enabled[i] ? 7 : divisor[i] == 0 ? top : std::min(top, shifted / divisor[i]);
            ASSERT_EQ(values[i], want) << dividend[i] << " << " << kShift << " / " << divisor[i] << " at PP " << p;
        }
        EXPECT_EQ(past_double > 0, dividend_bits == 48);
    }
}

// v wrapped to field f, as the PPs leave it.
std::int64_t wrapped_to(std::int64_t v, const PpField& f) {
    const std::int64_t bits = v & ((std::int64_t{1} << f.bits) - 1);
    return f.is_signed && bits >= (std::int64_t{1} << (f.bits - 1)) ? bits - (std::int64_t{1} << f.bits) : bits;
}

TEST(PpArray, ShiftedProductsKeepTheBitsOfTheWholeProduct) {
    // Signed factors whose shifted products end below, at and past bit 32, in 32-bit lanes: each result
    // is the whole product shifted and wrapped to its field, by a field and by a constant.
    struct Case {
        int a_bits, b_bits, shift;
    };
    for (const Case c : {Case{8, 8, 4}, Case{16, 15, 1}, Case{16, 16, 4}, Case{20, 16, 8}, Case{20, 13, 2}}) {
        SCOPED_TRACE(testing::Message() << c.a_bits << " x " << c.b_bits << " >> " << c.shift);
        constexpr int kPps = 1500;
        PpArray array(kPps, 1, 256, 64);
        std::mt19937_64 rng(static_cast<std::uint64_t>(c.a_bits * 100 + c.b_bits));
        const auto draw = [&](int bits) {
            return static_cast<std::int64_t>(rng() % (std::uint64_t{1} << bits)) - (std::int64_t{1} << (bits - 1));
        };
        std::vector<std::int64_t> a(kPps), b(kPps);
        for (int p = 0; p < kPps; ++p) {
            const auto i = static_cast<std::size_t>(p);
            a[i] = draw(c.a_bits);
            b[i] = draw(c.b_bits);
            array.write_backing(p, 0, c.a_bits, static_cast<std::uint64_t>(a[i]));
            array.write_backing(p, 32, c.b_bits, static_cast<std::uint64_t>(b[i]));
        }
        const std::int64_t imm = -(std::int64_t{1} << (c.b_bits - 1)) + 3;
        PpProgramBuilder builder("products", 256);
        const PpField fa = builder.load("a", 0, c.a_bits, true);
        const PpField fb = builder.load("b", 32, c.b_bits, true);
        const PpField product = builder.mul("product", fa, fb, c.shift);
        const PpField scaled = builder.mul_const("scaled", fa, imm, c.shift);
        const PpProgram program = builder.finish();
        array.run(program, PpSlotContext{});
        ASSERT_TRUE(array.ran_in_narrow_lanes());
        const auto products = array.field_values(product);
        const auto scaled_values = array.field_values(scaled);
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(products[i], wrapped_to((a[i] * b[i]) >> c.shift, product)) << a[i] << " x " << b[i];
            ASSERT_EQ(scaled_values[i], wrapped_to((a[i] * imm) >> c.shift, scaled)) << a[i] << " x " << imm;
        }
    }
}

TEST(PpArray, ShiftedProductsOfStaleValuesAreWrappedAsWideOnes) {
    // An 8-bit factor first written on half the PPs: the other half still hold what a 30-bit field
    // left in the same storage, so their products need more than 32 bits. Each result is still the
    // whole product shifted and wrapped to its field, as a run in 64-bit lanes leaves it.
    constexpr int kPps = 64;
    constexpr int kShift = 4;
    constexpr std::int64_t kStale = (std::int64_t{1} << 29) + 12345;
    PpArray array(kPps, 1, 256, 8);
    for (int p = 0; p < kPps; ++p) array.write_backing(p, 0, 1, static_cast<std::uint64_t>(p % 2));
    PpProgramBuilder b("stale_factor", 256);
    const PpField on = b.load("on", 0, 1, false);
    const PpField wide = b.set_const("wide", kStale, 30, false);
    const int wide_storage = wide.storage;
    b.release(wide);
    const PpField factor = b.alloc("factor", 8, false);
    ASSERT_EQ(factor.storage, wide_storage);  // the premise: the factor's lanes hold the 30-bit value
    const PpField other = b.set_const("other", 200, 8, false);
    b.enable_if(on, PpCompare::Equal, 1);
    b.assign_const(factor, 100);
    b.enable_all();
    const PpField product = b.mul("product", factor, other, kShift);
    const PpField scaled = b.mul_const("scaled", factor, 201, kShift);
    const PpProgram program = b.finish();
    array.run(program, PpSlotContext{});
    ASSERT_TRUE(array.ran_in_narrow_lanes());
    const auto products = array.field_values(product);
    const auto scaled_values = array.field_values(scaled);
    for (int p = 0; p < kPps; ++p) {
        const std::int64_t f = p % 2 == 1 ? 100 : kStale;
        EXPECT_EQ(products[static_cast<std::size_t>(p)], wrapped_to((f * 200) >> kShift, product)) << "PP " << p;
        EXPECT_EQ(scaled_values[static_cast<std::size_t>(p)], wrapped_to((f * 201) >> kShift, scaled)) << "PP " << p;
    }
}

// A random program of every operation over narrow fields (at most 31 bits), under random enable masks,
// with conditional updates and reused storage that leave stale values in disabled PPs, immediates past
// 32 bits, and every result stored. With `widen`, one more field of 41 bits is set at the end: that
// program runs in 64-bit lanes, the other in 32-bit ones.
PpProgram random_narrow_program(std::uint64_t seed, bool widen, int record_bits) {
    std::mt19937_64 rng(seed);
    const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
    const auto chance = [&](int percent) { return static_cast<int>(rng() % 100) < percent; };
    PpProgramBuilder b("random_narrow", 4096);
    std::vector<PpField> live;
    for (int i = 0; i < 4; ++i) {
        const int bits = 1 + static_cast<int>(pick(16));
        live.push_back(b.load("in", i * 16, bits, chance(50)));
    }
    // Stale wide values from the start: a 28-bit field's storage goes to a 4-bit one, set only where
    // a test passes, so the other PPs hold values far outside the small field's range.
    const PpField raw = b.load("raw", 0, 28, false);
    b.release(raw);
    b.enable_if(live[0], PpCompare::Less, static_cast<std::int64_t>(pick(8)));
    live.push_back(b.set_const("small", 5, 4, false));
    b.enable_all();
    // Products of full 16-bit values, past 32 bits before their shift.
    const PpField u0 = b.load("u0", 0, 16, false), u1 = b.load("u1", 16, 16, false);
    const PpField s0 = b.load("s0", 32, 16, true), s1 = b.load("s1", 48, 16, true);
    live.push_back(b.mul("unsigned_product", u0, u1, 6));
    live.push_back(b.mul("signed_product", s0, s1, 8));
    live.push_back(b.mul_const("scaled", s1, 70000, 7));
    // 32-bit unsigned fields, whose lanes hold values past 2^31, written whole and read by every
    // kind of operation below.
    live.push_back(b.mul("unsigned_32", u0, u1));
    live.push_back(b.mul_const("unsigned_32_const", u1, 65535));
    for (const PpField& f : {u0, u1, s0, s1}) b.release(f);
    int record = 64;
    bool masked = false;
    const std::int64_t immediates[] = {
        0, 1, -1, 3, -7, 255, 1000, -(std::int64_t{1} << 20), std::int64_t{1} << 35, -(std::int64_t{1} << 40)};
    for (int step = 0; step < 80; ++step) {
        // Under a partial mask, operands of at most 31 bits: a 32-bit unsigned result runs in 32-bit
        // lanes only when written whole.
        const auto operand = [&] {
            for (;;)
                if (const PpField f = live[pick(live.size())]; !masked || f.bits < 32) return f;
        };
        const PpField a = operand();
        const PpField c = operand();
        const std::int64_t imm = immediates[pick(std::size(immediates))];
        const int shift = static_cast<int>(pick(6));
        const auto narrow = [](PpField x, PpField y) { return std::max(x.bits, y.bits) < 28; };
        const auto large = [](std::int64_t v) { return v > (std::int64_t{1} << 30) || v < -(std::int64_t{1} << 30); };
        PpField result;
        try {
            switch (pick(15)) {
                // Operands narrow enough that every result fits 31 bits; a minimum or maximum with an
                // immediate past 32 bits keeps its operand.
                case 0: result = narrow(a, c) ? b.add("add", a, c) : PpField{}; break;
                case 1: result = narrow(a, c) ? b.sub("sub", a, c) : PpField{}; break;
                case 2: result = narrow(a, a) ? b.add_const("add_const", a, imm % 5000) : PpField{}; break;
                case 3: result = narrow(a, a) ? b.abs_diff_const("abs_diff", a, imm % 5000) : PpField{}; break;
                case 4: result = b.min_const("min", a, large(imm) ? std::int64_t{1} << 35 : imm); break;
                case 5: result = b.max_const("max", a, large(imm) ? -(std::int64_t{1} << 40) : imm); break;
                // Products past 32 bits, shifted back into a narrow field.
                case 6: result = a.bits + c.bits - 3 * shift <= 30 ? b.mul("mul", a, c, 3 * shift) : PpField{}; break;
                case 7:
                    result =
                        a.bits + 9 - 3 * shift <= 30 ? b.mul_const("mul_const", a, imm % 300, 3 * shift) : PpField{};
                    break;
                case 8: result = b.move("move", a, shift * 7); break;
                case 9: result = b.set_const("set", imm % 100000); break;
                case 10: {
                    const PpField dividend = b.max_const("dividend", a, 0);
                    const PpField divisor = b.max_const("divisor", c, 0);
                    result = b.div("div", dividend, divisor, shift, 1 + static_cast<int>(pick(20)));
                    b.release(dividend);
                    b.release(divisor);
                    break;
                }
                case 11: {
                    const PpField radicand = b.max_const("radicand", a, 0);
                    result = b.sqrt("sqrt", radicand);
                    b.release(radicand);
                    break;
                }
                case 12: {
                    if (a.bits > 12) continue;
                    const PpField index = b.max_const("index", a, 0);
                    PpTable table{"random", {}};
                    for (int v = 0; v < (1 << index.bits); ++v)
                        table.entries.push_back(static_cast<std::int64_t>(rng() % 2000) - 1000);
                    result = b.lookup("lookup", index, std::move(table), 11, true);
                    b.release(index);
                    break;
                }
                case 13: result = b.qee("qee", static_cast<int>(pick(2)), 24, true, shift); break;
                default: {
                    // A conditional update: the PPs that fail the test keep the field's old value.
                    const PpField target = b.set_const("target", imm % 50, 18, true);
                    b.enable_if(a, static_cast<PpCompare>(pick(6)), imm % 64);
                    masked = true;
                    b.assign(target, c);
                    result = target;
                    break;
                }
            }
        } catch (const std::invalid_argument&) {
            continue;  // a combination the builder refuses (a width past 48 bits, a negative operand)
        }
        if (!result.valid() || record + result.bits > record_bits) continue;
        b.store(result, record, result.bits);
        record += result.bits;
        live.push_back(result);
        // A released field's host storage goes to a later result, which a partial mask then leaves
        // holding the old field's values (wider than its own) in the disabled PPs.
        // (A 32-bit unsigned field keeps its storage: a field after it there must be written whole.)
        if (chance(40) && live.size() > 6) {
            const std::size_t gone = 4 + pick(live.size() - 4);
            if (live[gone].bits < 32) {
                b.release(live[gone]);
                live.erase(live.begin() + static_cast<std::ptrdiff_t>(gone));
            }
        }
        if (chance(30)) {
            b.enable_if(live[pick(live.size())], static_cast<PpCompare>(pick(6)), imm);
            masked = true;
        }
        if (chance(25)) {
            b.enable_all();
            masked = false;
        }
    }
    if (widen) b.set_const("widener", std::int64_t{1} << 40);
    return b.finish();
}

TEST(PpArray, NarrowAndWideLanesLeaveTheSameBits) {
    constexpr int kColumns = 40, kRows = 60, kRecordBits = 4096;  // three blocks, the last one partial
    const QeeCoefficients qee[2] = {{3, -5, 7, -11000, 130, -(std::int64_t{1} << 21)}, {0, 0, 0, 77, -91, 5}};
    int narrow_programs = 0;
    for (std::uint64_t seed = 1; seed <= 24; ++seed) {
        const PpProgram narrow = random_narrow_program(seed, false, kRecordBits);
        const PpProgram wide = random_narrow_program(seed, true, kRecordBits);
        const auto widest = [](const PpProgram& p) {
            int bits = 0;
            for (const PpField& f : p.fields) bits = std::max(bits, f.bits);
            return bits;
        };
        ASSERT_GT(widest(wide), 32);
        if (widest(narrow) > 32) continue;  // a wide program after all; the others count
        PpArray in_narrow(kColumns, kRows, 4096, kRecordBits), in_wide(kColumns, kRows, 4096, kRecordBits);
        std::mt19937_64 rng(seed * 977);
        for (int p = 0; p < kColumns * kRows; ++p) {
            const std::uint64_t inputs = rng();
            in_narrow.write_backing(p, 0, 64, inputs);
            in_wide.write_backing(p, 0, 64, inputs);
        }
        const PpSlotContext context{0, qee};
        const PpRunCounts counts = in_narrow.run(narrow, context);
        in_wide.run(wide, context);
        ASSERT_FALSE(in_wide.ran_in_narrow_lanes());
        if (in_narrow.ran_in_narrow_lanes()) ++narrow_programs;
        for (int p = 0; p < kColumns * kRows; ++p) {
            for (int bit = 64; bit < kRecordBits; bit += 64)
                ASSERT_EQ(in_narrow.read_backing(p, bit, 64), in_wide.read_backing(p, bit, 64))
                    << "seed " << seed << ", PP " << p << ", bits from " << bit;
        }
        EXPECT_GT(counts.instructions, 60u);
    }
    EXPECT_GE(narrow_programs, 16);
}

TEST(PpArray, ThirtyTwoBitUnsignedFieldsRunNarrowOnlyWhereNoStaleBitsCanMeetThem) {
    // A 32-bit unsigned field's lane holds its value's bits; read as the value, it is zero-extended.
    // Where a PP could read such bits as another field's, or another field's (negative) value as such
    // a field's, the program must run in 64-bit lanes. Each case runs as built and widened, and must
    // leave the same bits; `narrow` says which lanes the case may use.
    constexpr int kColumns = 40, kRows = 60;
    const auto fill = [](PpArray& array) {
        std::mt19937_64 rng(5);
        for (int p = 0; p < array.size(); ++p) array.write_backing(p, 0, 64, rng());
    };
    // Shared opening: a signed field leaves negative values in a slot, then `body` runs.
    const auto build = [](bool widen, const std::function<void(PpProgramBuilder&)>& body) {
        PpProgramBuilder b("unsigned_32", 1024);
        const PpField negative = b.load("negative", 40, 20, true);
        const PpField kept = b.add_const("kept", negative, -3);  // stored at the end, whatever happens
        b.release(negative);
        body(b);
        b.store(kept, 600, kept.bits);
        if (widen) b.set_const("widener", std::int64_t{1} << 40);
        return b.finish();
    };
    const auto product = [](PpProgramBuilder& b) {
        const PpField x = b.load("x", 0, 16, false), y = b.load("y", 16, 16, false);
        const PpField p = b.mul("product", x, y);  // 32 bits unsigned
        b.release(x);
        b.release(y);
        return p;
    };
    const auto compare = [&](const char* name, bool narrow, const std::function<void(PpProgramBuilder&)>& body) {
        PpArray as_built(kColumns, kRows, 1024, 1024), widened(kColumns, kRows, 1024, 1024);
        fill(as_built);
        fill(widened);
        as_built.run(build(false, body), PpSlotContext{});
        widened.run(build(true, body), PpSlotContext{});
        EXPECT_EQ(as_built.ran_in_narrow_lanes(), narrow) << name;
        for (int p = 0; p < as_built.size(); ++p)
            for (int bit = 64; bit < 1024; bit += 64)
                ASSERT_EQ(as_built.read_backing(p, bit, 64), widened.read_backing(p, bit, 64)) << name << ", PP " << p;
    };
    // Written whole, read by operations that look at its value: 32-bit lanes.
    compare("whole", true, [&](PpProgramBuilder& b) {
        const PpField u = product(b);
        b.store(b.sqrt("root", u), 64, 16);
        b.store(b.move("high", u, 20), 96, 12);
        b.store(b.min_const("least", u, std::int64_t{3} << 30), 128, 32);
        b.enable_if(u, PpCompare::Greater, std::int64_t{3} << 29);
        b.store(b.set_const("big", 1, 1, false), 192, 1);
        b.enable_all();
    });
    // Written under a mask over a slot of negative values: the other PPs' values would be read as its.
    compare("written in part", false, [&](PpProgramBuilder& b) {
        const PpField on = b.load("on", 32, 1, false);
        b.enable_if(on, PpCompare::Equal, 1);
        const PpField u = product(b);
        b.enable_all();
        b.store(b.min_const("least", u, std::int64_t{3} << 30), 128, 32);
    });
    // A field after it in its slot, written under a mask: its other PPs would read the product's bits.
    compare("followed in part", false, [&](PpProgramBuilder& b) {
        const PpField on = b.load("on", 32, 1, false);
        const PpField u = product(b);
        b.store(u, 64, 32);
        b.release(u);
        b.enable_if(on, PpCompare::Equal, 1);
        const PpField after = b.set_const("after", -5, 8, true);
        b.enable_all();
        b.store(b.min_const("least", after, 100), 128);
    });
    // One program leaves a product's bits in a slot; the next reads that slot as a field of its own
    // before writing it. It runs in 64-bit lanes, the bits widened as the value they stand for.
    const auto leave = [](bool widen) {
        PpProgramBuilder b("leave", 1024);
        const PpField x = b.load("x", 0, 16, false), y = b.load("y", 16, 16, false);
        b.mul("product", x, y);  // storage slot 2
        if (widen) b.set_const("widener", std::int64_t{1} << 40);
        return b.finish();
    };
    const auto read_on = [](bool widen) {
        PpProgramBuilder b("read_on", 1024);
        b.alloc("pad0", 8, false);
        b.alloc("pad1", 8, false);
        const PpField carried = b.alloc("carried", 31, false);  // storage slot 2, read before any write
        b.store(b.min_const("carried_least", carried, std::int64_t{1} << 30), 64);
        if (widen) b.set_const("widener", std::int64_t{1} << 40);
        return b.finish();
    };
    PpArray as_built(kColumns, kRows, 1024, 1024), widened(kColumns, kRows, 1024, 1024);
    fill(as_built);
    fill(widened);
    as_built.run(leave(false), PpSlotContext{});
    EXPECT_TRUE(as_built.ran_in_narrow_lanes());
    as_built.run(read_on(false), PpSlotContext{});
    EXPECT_FALSE(as_built.ran_in_narrow_lanes());
    widened.run(leave(true), PpSlotContext{});
    widened.run(read_on(true), PpSlotContext{});
    for (int p = 0; p < as_built.size(); ++p)
        ASSERT_EQ(as_built.read_backing(p, 64, 64), widened.read_backing(p, 64, 64)) << "carried, PP " << p;
}

TEST(PpArray, CandidateRunsKeepThirtyTwoBitUnsignedBitsOutOfTheirLanes) {
    // A run over candidates writes only their lanes, so it uses 32-bit lanes only with no 32-bit
    // unsigned field of its own and none left in the array's slots.
    const auto fill = [](PpArray& array) {
        for (int p = 0; p < array.size(); ++p)
            array.write_backing(p, 0, 64, static_cast<std::uint64_t>(p) * 0x9E3779B97F4A7C15ull);
    };
    PpArray array(64, 4, 1024, 256);
    fill(array);
    std::vector<int> candidates;
    for (int p = 0; p < array.size(); ++p)
        if ((array.read_backing(p, 0, 8) & 0xFF) > 200) candidates.push_back(p);
    const auto listed = [](bool with_product) {
        PpProgramBuilder b("listed", 1024);
        const PpField x = b.load("x", 0, 8, false);
        PpField y;  // a 32-bit unsigned product, written whole before the test, or a byte
        if (with_product) y = b.mul("product", b.load("u", 8, 16, false), b.load("v", 24, 16, false));
        b.enable_if(x, PpCompare::Greater, 200);  // rules out every PP but the candidates
        if (!with_product) y = b.add_const("y", x, 1);
        b.store(y, 64, y.bits);
        return b.finish();
    };
    array.run_candidates(listed(false), PpSlotContext{}, candidates);
    EXPECT_TRUE(array.ran_in_narrow_lanes());
    array.run_candidates(listed(true), PpSlotContext{}, candidates);
    EXPECT_FALSE(array.ran_in_narrow_lanes());
    // On a fresh array, a whole run leaves a product's bits in a slot; the next candidate run widens
    // them. (The array above holds products past 2^31 in 64-bit lanes now, so it stays there.)
    PpArray fresh(64, 4, 1024, 256);
    fill(fresh);
    PpProgramBuilder b("leave", 1024);
    b.mul("product", b.load("u", 8, 16, false), b.load("v", 24, 16, false));
    fresh.run(b.finish(), PpSlotContext{});
    EXPECT_TRUE(fresh.ran_in_narrow_lanes());
    fresh.run_candidates(listed(false), PpSlotContext{}, candidates);
    EXPECT_FALSE(fresh.ran_in_narrow_lanes());
    EXPECT_GT(candidates.size(), 10u);
}

TEST(PpArray, FieldsCarryTheirValuesBetweenProgramsOfEitherLaneWidth) {
    // Field 0 is state kept from one program to the next, as local memory keeps it: each program clamps
    // it and adds to it. Programs of narrow fields follow programs with a field past 32 bits,
    // one of which leaves a value past 32 bits in the state. The same sequence with every program
    // widened (all in 64-bit lanes) must leave the same state after every program.
    const auto program = [](int bits, std::int64_t addend, bool widen) {
        PpProgramBuilder b("step", 208);
        const PpField state = b.alloc("state", bits, true);
        // Clamped first, so that the comparisons see the state's whole value.
        const std::int64_t room = std::abs(addend);
        const PpField low = b.min_const("low", state, state.max_value() - room);
        const PpField clamped = b.max_const("clamped", low, state.min_value() + room);
        b.assign(state, b.add_const("next", clamped, addend));
        if (widen) b.set_const("widener", std::int64_t{1} << 39);
        return b.finish();
    };
    struct Step {
        int bits;
        std::int64_t addend;
        bool widen;
    };
    const Step steps[] = {
        {30, 1000, true}, {30, -3, false}, {20, 7, false}, {30, 1000, true}, {40, std::int64_t{1} << 36, false},
        {30, 1, false},   {20, -5, false}, {25, 9, false}};
    PpArray mixed(50, 30, 208, 64), wide(50, 30, 208, 64);  // two blocks
    for (const Step& step : steps) {
        const PpProgram as_is = program(step.bits, step.addend, step.widen);
        mixed.run(as_is, PpSlotContext{});
        wide.run(program(step.bits, step.addend, true), PpSlotContext{});
        ASSERT_EQ(mixed.field_values(as_is.fields[0]), wide.field_values(as_is.fields[0]))
            << step.bits << "-bit state plus " << step.addend;
    }
    EXPECT_NE(mixed.field_values(program(20, 0, false).fields[0])[0], 0);
}

TEST(PpArray, StorageIsReusedAcrossDifferentPrograms) {
    // Two programs with differently shaped fields, alternately on one array: each run's results are
    // those of a fresh array.
    auto program_of = [](int bits, std::int64_t k) {
        PpProgramBuilder b(bits == 8 ? "p8" : "p4", 208);
        const PpField x = b.load("x", 0, bits, true);
        b.mul_const("y", x, k);
        return b.finish();
    };
    const PpProgram p8 = program_of(8, 3);
    const PpProgram p4 = program_of(4, -5);
    const PpField y8 = p8.fields[1];
    const PpField y4 = p4.fields[1];
    auto fill = [](PpArray& a) {
        for (int p = 0; p < a.size(); ++p) a.write_backing(p, 0, 8, static_cast<std::uint64_t>(p * 7));
    };
    PpArray fresh8(40, 30, 208, 64), fresh4(40, 30, 208, 64), shared(40, 30, 208, 64);
    fill(fresh8);
    fill(fresh4);
    fill(shared);
    fresh8.run(p8, PpSlotContext{});
    fresh4.run(p4, PpSlotContext{});
    const std::vector<std::int64_t> want8 = fresh8.field_values(y8);
    const std::vector<std::int64_t> want4 = fresh4.field_values(y4);
    for (int round = 0; round < 2; ++round) {
        shared.run(p8, PpSlotContext{});
        EXPECT_EQ(shared.field_values(y8), want8);
        shared.run(p4, PpSlotContext{});
        EXPECT_EQ(shared.field_values(y4), want4);
    }
    EXPECT_EQ(want4[1], -35);  // 7 as a signed 4-bit field is 7; times -5
    EXPECT_THROW(shared.field_values(PpField{9, 0, 8, false}), std::out_of_range);
    EXPECT_THROW(shared.field_values(PpField{}), std::out_of_range);
}

TEST(PpArray, RefusesWhatItCannotRunBeforeChangingAnything) {
    PpArray array(8, 8, 100, 128);
    for (int p = 0; p < array.size(); ++p) array.write_backing(p, 0, 16, 0xBEEF);

    PpProgramBuilder big("big", 208);
    big.alloc("wide", 48, false);
    big.alloc("wider", 48, false);
    big.alloc("widest", 48, false);  // 144 bits: the array's PPs have 100
    EXPECT_THROW(array.run(big.finish(), PpSlotContext{}), std::invalid_argument);

    PpProgramBuilder qee("qee", 100);
    qee.qee("q", 1, 8, false, 0);  // needs two expressions
    const QeeCoefficients q{};
    EXPECT_THROW(array.run(qee.finish(), PpSlotContext{0, one(q)}), std::invalid_argument);

    // A store that would run, then a load past the store's end: nothing is stored.
    PpProgramBuilder past("past", 100);
    const PpField zero = past.set_const("zero", 0, 16, false);
    past.store(zero, 0);
    past.load("late", 90, 30, false);  // record bits 90..119
    const PpProgram past_program = past.finish();
    try {
        array.run(past_program, PpSlotContext{10, {}});  // bits 100..129 of a 128-bit store
        FAIL() << "a load past the backing store";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("past the 128-bit backing store"), std::string::npos) << e.what();
    }
    EXPECT_THROW(array.run(past_program, PpSlotContext{-200, {}}), std::invalid_argument);
    for (int p = 0; p < array.size(); ++p) ASSERT_EQ(array.read_backing(p, 10, 16), 0xBEEFu >> 10);

    // With the record at bit 0 it runs, and the store lands.
    EXPECT_NO_THROW(array.run(past_program, PpSlotContext{0, {}}));
    EXPECT_EQ(array.read_backing(0, 0, 16), 0u);
}

}  // namespace
}  // namespace pp5
