#include "sim/pixel_processors/pp_array.h"

#include "sim/pixel_processors/pp_integer.h"
#include "sim/pixel_processors/pp_program_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <new>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace pp5 {

namespace {

// Lane types. A program whose every field has at most 32 bits runs in 32-bit lanes (twice as many PPs
// per vector instruction, half the memory) when PpNarrowPlan allows; any other in 64-bit lanes. Each
// lane holds its field's value exactly, in two's complement, so both give the same integers: the
// narrow executor computes in 32 bits only where the low 32 bits of a result are all that its wrap
// keeps (sums, differences, unshifted products), and widens to 64 bits wherever higher bits matter
// (shifted products, quotients, roots, the QEE).
template <class Lane>
using Unsigned = std::make_unsigned_t<Lane>;

template <class Lane>
constexpr int kLaneBits = static_cast<int>(sizeof(Lane) * 8);

// PPs never exchange values, so the whole program runs over one block of PPs after another: the
// same results, with each block's fields small enough to stay in the host's cache.
constexpr std::size_t kBlockLanes = 1024;

}  // namespace

// How a program runs in 32-bit lanes. Fields of up to 31 bits, and signed ones of 32, hold their
// values and are read with sign extension. A 32-bit unsigned field holds its value's 32 bits and is
// read with zero extension; the lanes agree with 64-bit ones as long as no PP ever reads, as one kind
// of field, bits written as the other kind. narrow_plan makes sure of that from the program alone:
// - every 32-bit unsigned field is first written with every PP enabled, before any read;
// - in a storage slot, every field after such a field is first written with every PP enabled;
// and PpArray::choose_narrow_lanes checks the rest at run time: a slot whose lanes hold a 32-bit
// unsigned field's bits from an earlier program is first written whole by this one.
struct PpNarrowPlan {
    std::vector<std::uint8_t> zero_extended;        // by field id
    std::vector<std::uint8_t> first_written_whole;  // by storage slot: its first field's first access
    std::vector<std::uint8_t> ends_zero_extended;   // by storage slot: what its last written field leaves
    std::vector<std::uint8_t> written;              // by storage slot: some field of this program writes it
};

namespace {

std::optional<PpNarrowPlan> narrow_plan(const PpProgram& program) {
    const std::size_t fields = program.fields.size();
    PpNarrowPlan plan;
    plan.zero_extended.assign(fields, 0);
    for (std::size_t f = 0; f < fields; ++f) {
        const PpField& field = program.fields[f];
        if (field.bits > 32) return std::nullopt;
        plan.zero_extended[f] = field.bits == 32 && !field.is_signed ? 1 : 0;
    }
    // Each field's first access: a read, or a write with every PP enabled ("whole") or not.
    enum class Access : std::uint8_t { None, Read, PartWrite, WholeWrite };
    std::vector<Access> first(fields, Access::None);
    std::vector<std::uint8_t> is_written(fields, 0);
    bool all_enabled = true;
    for (const PpInstruction& in : program.instructions) {
        for (const int read : {in.a, in.b})
            if (read >= 0 && first[static_cast<std::size_t>(read)] == Access::None)
                first[static_cast<std::size_t>(read)] = Access::Read;
        if (in.dst >= 0) {
            const auto d = static_cast<std::size_t>(in.dst);
            if (first[d] == Access::None) first[d] = all_enabled ? Access::WholeWrite : Access::PartWrite;
            is_written[d] = 1;
        }
        if (in.op == PpOp::EnableIf) all_enabled = false;
        if (in.op == PpOp::EnableAll) all_enabled = true;
    }
    const auto slots = static_cast<std::size_t>(std::max(program.storage_slots, 0));
    plan.first_written_whole.assign(slots, 1);
    plan.ends_zero_extended.assign(slots, 0);
    plan.written.assign(slots, 0);
    std::vector<std::uint8_t> seen(slots, 0), after_zero_extended(slots, 0);
    for (std::size_t f = 0; f < fields; ++f) {  // in id order: a slot's fields in the order they held it
        if (first[f] == Access::None) continue;
        const auto slot = static_cast<std::size_t>(program.fields[f].storage);
        if (slot >= slots) return std::nullopt;
        const bool whole = first[f] == Access::WholeWrite;
        if ((plan.zero_extended[f] || after_zero_extended[slot]) && !whole) return std::nullopt;
        if (!seen[slot]) plan.first_written_whole[slot] = whole ? 1 : 0;
        seen[slot] = 1;
        if (plan.zero_extended[f]) after_zero_extended[slot] = 1;
        if (is_written[f]) {
            plan.written[slot] = 1;
            plan.ends_zero_extended[slot] = plan.zero_extended[f];
        }
    }
    return plan;
}

// The lane holding v modulo 2^lane bits.
template <class Lane>
Lane to_lane(std::int64_t v) {
    return static_cast<Lane>(static_cast<Unsigned<Lane>>(static_cast<std::uint64_t>(v)));
}

// Whether an immediate is a value of the lane type (then comparisons and minima can stay narrow).
template <class Lane>
bool lane_holds(std::int64_t v) {
    return v >= std::numeric_limits<Lane>::min() && v <= std::numeric_limits<Lane>::max();
}

// What bit-serial hardware leaves in a field of `bits` bits: the value modulo 2^bits, read as two's
// complement when the field is signed. ((v & mask) ^ sign) - sign sign-extends with operations every
// x86-64 vector unit has (no arithmetic shift needed); sign = 0 for unsigned. A field never has more
// bits than its lane, so the wrap needs only the lane's bits of a value.
template <class Lane>
struct Wrap {
    Unsigned<Lane> mask;
    Unsigned<Lane> sign;

    explicit Wrap(const PpField& f)
        : mask(static_cast<Unsigned<Lane>>(f.bits >= 64 ? ~0ull : (1ull << f.bits) - 1)),
          sign(static_cast<Unsigned<Lane>>(f.is_signed ? 1ull << (f.bits - 1) : 0)) {}
    Lane operator()(Lane v) const { return static_cast<Lane>(((static_cast<Unsigned<Lane>>(v) & mask) ^ sign) - sign); }
};

// For values known to fit their field already.
struct NoWrap {
    template <class Lane>
    Lane operator()(Lane v) const {
        return v;
    }
};

// pp_isqrt without its loops, so that it vectorises: floor(sqrt(x)), 0 for x <= 0. The double estimate
// is exact below 2^52 but for a value a hair under a perfect square, which one correction each way
// mends; every value the builder lets a field hold fits 48 bits. A disabled PP's stale value may be
// anything: its result, discarded, stays defined (unsigned products, a square root of at most 2^63).
std::int64_t isqrt_branch_free(std::int64_t x) {
    const std::int64_t v = std::max<std::int64_t>(x, 0);
    const auto r = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(v)));
    const auto u = static_cast<std::uint64_t>(v);
    const std::uint64_t down = r - (r * r > u ? 1 : 0);
    return static_cast<std::int64_t>(down + ((down + 1) * (down + 1) <= u ? 1 : 0));
}

// floor(a / b) for a >= 0, b > 0: a double estimate, corrected (exact for the fields' widths).
std::int64_t exact_quotient(std::int64_t a, std::int64_t b) {
    if (a >= (std::int64_t{1} << 52)) return a / b;
    auto q = static_cast<std::int64_t>(static_cast<double>(a) / static_cast<double>(b));
    if (q * b > a) --q;
    else if ((q + 1) * b <= a) ++q;
    return q;
}

// A Div instruction's result where a <= largest_a and a << shift fits 52 bits: floor((a << shift) / b),
// or `top` when b <= 0, a < 0 or the quotient is past it. The double quotient of two exact operands
// is at least the true floor and at most one above it; the corrections settle it. A divisor past the
// dividend is clamped (the quotient is 0 either way), so every product stays far inside 64 bits.
// Written with masks, not branches, so that a block of divides vectorises: a PP outside the domain
// (a disabled PP's stale value, say) divides 0 by 1, and is given `top`.
[[gnu::always_inline]] inline std::int64_t divide_in_double(std::int64_t a, std::int64_t b, int shift,
                                                            std::int64_t largest_a, std::int64_t top) {
    const std::int64_t in_domain = -static_cast<std::int64_t>((b > 0) & (a >= 0) & (a <= largest_a));  // all ones
    const std::int64_t dividend = static_cast<std::int64_t>(static_cast<std::uint64_t>(a) << shift) & in_domain;
    const std::int64_t divisor = (std::min(b, dividend + 1) & in_domain) | (~in_domain & 1);
    auto q = static_cast<std::int64_t>(static_cast<double>(dividend) / static_cast<double>(divisor));
    q -= q * divisor > dividend ? 1 : 0;
    q += (q + 1) * divisor <= dividend ? 1 : 0;
    return std::min(q | (~in_domain & top), top);
}

// The lanes of a block whose PP is enabled, in order, into `lanes`; returns how many. Enable bytes
// are 0 or 1 and are read eight at a time, so a sparse block costs little more than its enabled PPs.
std::size_t enabled_lanes(std::size_t n, const std::uint8_t* en, std::uint16_t* lanes) {
    std::size_t count = 0;
    std::size_t p = 0;
    for (; p + 8 <= n; p += 8) {
        std::uint64_t bytes;
        std::memcpy(&bytes, en + p, sizeof bytes);
        for (; bytes != 0; bytes &= bytes - 1)
            lanes[count++] = static_cast<std::uint16_t>(p + static_cast<std::size_t>(std::countr_zero(bytes)) / 8);
    }
    for (; p < n; ++p)
        if (en[p]) lanes[count++] = static_cast<std::uint16_t>(p);
    return count;
}

// Div over one block: dst = (a << shift) / b on every enabled PP. A restoring divide saturates: b <= 0,
// or a quotient past the field, gives the field's maximum, `top`. (The builder keeps a << shift within
// 63 bits; a stale a past that also saturates.) A divide is usually guarded by a test that leaves few
// PPs enabled, and the host's divider is slow, so then only the enabled PPs' operands are gathered and
// divided. Shifted dividends of at most 52 bits, all the builder's fields give, are divided in
// doubles, vectorised; a block where an enabled PP holds a larger one is divided PP by PP, exactly.
template <class Lane, class WidenA, class WidenB>
[[gnu::always_inline]] inline void divide_block(std::size_t n, const std::uint8_t* en, std::uint64_t enabled_count,
                                                Lane* dst, const Lane* a, const Lane* b, WidenA wide_a, WidenB wide_b,
                                                int shift, std::int64_t top) {
    const std::int64_t largest_a = std::numeric_limits<std::int64_t>::max() >> shift;
    const std::int64_t largest_in_double = ((std::int64_t{1} << 52) - 1) >> shift;
    std::array<std::int64_t, kBlockLanes> dividends, divisors;
    std::array<std::uint16_t, kBlockLanes> lanes;
    std::array<std::uint8_t, kBlockLanes> enabled;  // of the lanes divided
    const bool gathered = enabled_count * 4 < n;
    std::size_t m = n;
    if (gathered) {
        m = enabled_lanes(n, en, lanes.data());
        for (std::size_t i = 0; i < m; ++i) {
            dividends[i] = wide_a(a[lanes[i]]);
            divisors[i] = wide_b(b[lanes[i]]);
        }
        std::fill_n(enabled.begin(), m, std::uint8_t{1});
    } else {
        for (std::size_t p = 0; p < n; ++p) {
            dividends[p] = wide_a(a[p]);
            divisors[p] = wide_b(b[p]);
        }
        std::copy_n(en, n, enabled.begin());
    }
    std::uint8_t beyond_double = 0;
    for (std::size_t i = 0; i < m; ++i)
        beyond_double |= static_cast<std::uint8_t>(enabled[i] & (dividends[i] > largest_in_double));
    if (!beyond_double) {
        for (std::size_t i = 0; i < m; ++i)
            dividends[i] = divide_in_double(dividends[i], divisors[i], shift, largest_in_double, top);
    } else {
        for (std::size_t i = 0; i < m; ++i) {
            const std::int64_t dividend = dividends[i];
            const std::int64_t divisor = divisors[i];
            const bool defined = divisor > 0 && dividend >= 0 && dividend <= largest_a;
            dividends[i] = defined ? std::min(exact_quotient(dividend << shift, divisor), top) : top;
        }
    }
    if (gathered) {
        for (std::size_t i = 0; i < m; ++i) dst[lanes[i]] = static_cast<Lane>(dividends[i]);
    } else {
        for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? static_cast<Lane>(dividends[p]) : dst[p];
    }
}

// Arithmetic in the unsigned type, where overflow is defined: a PP that is disabled may hold a stale
// value from an earlier program, and its (discarded) result must not be undefined behaviour.
template <class Lane>
Lane add_lanes(Lane a, Lane b) {
    return static_cast<Lane>(static_cast<Unsigned<Lane>>(a) + static_cast<Unsigned<Lane>>(b));
}
template <class Lane>
Lane sub_lanes(Lane a, Lane b) {
    return static_cast<Lane>(static_cast<Unsigned<Lane>>(a) - static_cast<Unsigned<Lane>>(b));
}
template <class Lane>
Lane mul_lanes(Lane a, Lane b) {
    return static_cast<Lane>(static_cast<Unsigned<Lane>>(a) * static_cast<Unsigned<Lane>>(b));
}

// dst[p] = wrap(value(p)) on every enabled PP; a disabled PP keeps its value. `value` may compute in
// 64 bits for a 32-bit lane: the lane keeps the low bits, all the wrap looks at. Both loops are plain
// loops over contiguous arrays that GCC vectorises.
template <class Lane, class WrapTo, class Value>
[[gnu::always_inline]] inline void for_enabled(std::size_t n, const std::uint8_t* enabled, bool all, Lane* dst,
                                               WrapTo wrap, Value&& value) {
    const auto result = [&](std::size_t p) { return wrap(static_cast<Lane>(value(p))); };
    if (all) {
        for (std::size_t p = 0; p < n; ++p) dst[p] = result(p);
    } else {
        // A branch-free blend.
        for (std::size_t p = 0; p < n; ++p) {
            const Lane keep = static_cast<Lane>(enabled[p]) - 1;  // 0 where enabled, all ones where not
            dst[p] = (result(p) & ~keep) | (dst[p] & keep);
        }
    }
}

// enable[p] &= cmp(a[p], imm); returns how many PPs stay enabled.
template <class Lane, class Value, class Compare>
[[gnu::always_inline]] inline std::uint64_t and_enable(std::size_t n, std::uint8_t* enabled, const Lane* a, Value imm,
                                                       Compare cmp) {
    std::uint64_t count = 0;
    for (std::size_t p = 0; p < n; ++p) {
        const auto e =
            static_cast<std::uint8_t>(enabled[p] & static_cast<std::uint8_t>(cmp(static_cast<Value>(a[p]), imm)));
        enabled[p] = e;
        count += e;
    }
    return count;
}

template <class Lane, class Value>
[[gnu::always_inline]] inline std::uint64_t enable_where_compared(std::size_t n, std::uint8_t* enabled, const Lane* a,
                                                                  PpCompare c, Value imm) {
    switch (c) {
        case PpCompare::Less: return and_enable(n, enabled, a, imm, std::less<>());
        case PpCompare::LessEqual: return and_enable(n, enabled, a, imm, std::less_equal<>());
        case PpCompare::Equal: return and_enable(n, enabled, a, imm, std::equal_to<>());
        case PpCompare::NotEqual: return and_enable(n, enabled, a, imm, std::not_equal_to<>());
        case PpCompare::GreaterEqual: return and_enable(n, enabled, a, imm, std::greater_equal<>());
        case PpCompare::Greater: return and_enable(n, enabled, a, imm, std::greater<>());
    }
    return 0;
}

// Inlined into run(), so that it is compiled for each of run()'s target clones. The comparison stays in
// the lane's width when the immediate is one of its values, and widens otherwise.
template <class Lane>
[[gnu::always_inline]] inline std::uint64_t enable_where(std::size_t n, std::uint8_t* enabled, const Lane* a,
                                                         PpCompare c, std::int64_t imm) {
    if (lane_holds<Lane>(imm)) return enable_where_compared(n, enabled, a, c, static_cast<Lane>(imm));
    return enable_where_compared(n, enabled, a, c, imm);
}

// dst[p] = table[a[p] & last] on enabled PPs. Kept out of run()'s AVX2 clone on purpose: there it
// becomes a vector gather, slower than scalar loads on some x86-64 hosts (AMD Zen).
template <class Lane, class WrapTo>
[[gnu::noinline]] void lookup_loop(std::size_t n, const std::uint8_t* enabled, bool all, Lane* dst, WrapTo wrap,
                                   const Lane* a, const std::int64_t* table, std::uint64_t last) {
    for_enabled(n, enabled, all, dst, wrap,
                [&](std::size_t p) { return table[static_cast<std::uint64_t>(a[p]) & last]; });
}

}  // namespace

PpRunCounts& PpRunCounts::operator+=(const PpRunCounts& other) {
    instructions += other.instructions;
    pp_operations += other.pp_operations;
    enabled_pp_operations += other.enabled_pp_operations;
    return *this;
}

PpArray::PpArray(int columns, int rows, int local_memory_bits, int backing_store_bits)
    : columns_(columns),
      rows_(rows),
      local_memory_bits_(local_memory_bits),
      backing_store_bits_(backing_store_bits),
      // Sizes are checked below, before any field is stored.
      narrow_fields_(static_cast<std::size_t>(std::max(columns, 0)) * static_cast<std::size_t>(std::max(rows, 0))),
      wide_fields_(narrow_fields_.lanes()) {
    if (columns < 1 || rows < 1 || local_memory_bits < 1 || backing_store_bits < 0) {
        throw std::invalid_argument(
            fmt::format("PpArray: {} x {} PPs, {} bits of local memory, {} of backing store: "
                        "sizes must be positive",
                        columns, rows, local_memory_bits, backing_store_bits));
    }
    if (static_cast<std::int64_t>(columns) * rows > (std::int64_t{1} << 30)) {
        throw std::invalid_argument(fmt::format("PpArray: {} x {} PPs is too many", columns, rows));
    }
    backing_words_ = (backing_store_bits + 63) / 64;
    const std::size_t words =
        std::max<std::size_t>(1, static_cast<std::size_t>(size()) * static_cast<std::size_t>(backing_words_));
    backing_.reset(static_cast<std::uint64_t*>(std::calloc(words, sizeof(std::uint64_t))));
    if (!backing_) throw std::bad_alloc();
    enabled_.assign(static_cast<std::size_t>(size()), 1);
}

void PpArray::write_backing(int pp, int bit_offset, int bits, std::uint64_t value) {
    backing_writer(bit_offset, bits).write(pp, value);
}

std::uint64_t PpArray::read_backing(int pp, int bit_offset, int bits) const {
    return backing_reader(bit_offset, bits).read(pp);
}

PpBackingReader PpArray::backing_reader(int bit_offset, int bits) const {
    check_backing_range(bit_offset, bits);
    return {backing_.get(), static_cast<std::size_t>(size()), bit_offset, bits};
}

PpBackingWriter PpArray::backing_writer(int bit_offset, int bits) {
    check_backing_range(bit_offset, bits);
    return {backing_.get(), static_cast<std::size_t>(size()), bit_offset, bits};
}

void PpArray::check_backing_range(int bit_offset, int bits) const {
    if (bits < 1 || bits > 64 || bit_offset < 0 || bit_offset > backing_store_bits_ - bits) {
        throw std::out_of_range(
            fmt::format("PP backing store: {} bits at {} (store of {} bits)", bits, bit_offset, backing_store_bits_));
    }
}

std::vector<std::int64_t> PpArray::field_values(const PpField& field) const {
    const auto values = [&](const auto& fields) {
        if (field.storage < 0 || field.storage >= static_cast<int>(fields.slots())) {
            throw std::out_of_range(
                fmt::format("PpArray: no field with id {} (storage {}) in the last run", field.id, field.storage));
        }
        const auto slot = fields.values(static_cast<std::size_t>(field.storage));
        std::vector<std::int64_t> out(slot.begin(), slot.end());
        if (narrow_current_ && field.bits == 32 && !field.is_signed)
            for (std::int64_t& v : out) v = static_cast<std::int64_t>(static_cast<std::uint32_t>(v));
        return out;
    };
    return narrow_current_ ? values(narrow_fields_) : values(wide_fields_);
}

const PpNarrowPlan* PpArray::choose_narrow_lanes(const std::optional<PpNarrowPlan>& plan) {
    bool narrow = plan.has_value();
    if (narrow && narrow_current_) {
        // Bits a 32-bit unsigned field left in a slot must not be read as another field's.
        for (std::size_t slot = 0; slot < plan->first_written_whole.size() && slot < zero_extended_slots_.size();
             ++slot)
            if (zero_extended_slots_[slot] && !plan->first_written_whole[slot]) narrow = false;
    }
    if (narrow && !narrow_current_) {
        for (std::size_t slot = 0; slot < wide_fields_.slots() && narrow; ++slot) {
            const auto values = wide_fields_.values(slot);
            narrow = std::all_of(values.begin(), values.end(), lane_holds<std::int32_t>);
        }
    }
    if (narrow != narrow_current_) {
        // Exact either way: every value fits the lanes chosen, and each slot is widened as its field
        // is read. Slots the other lanes never had hold 0, as new ones do.
        if (narrow) {
            narrow_fields_.assign_converted(wide_fields_,
                                            [](std::size_t, std::int64_t v) { return static_cast<std::int32_t>(v); });
            zero_extended_slots_.assign(wide_fields_.slots(), 0);
        } else {
            wide_fields_.assign_converted(narrow_fields_, [&](std::size_t slot, std::int32_t v) {
                const bool zero = slot < zero_extended_slots_.size() && zero_extended_slots_[slot];
                return zero ? static_cast<std::int64_t>(static_cast<std::uint32_t>(v)) : static_cast<std::int64_t>(v);
            });
        }
        narrow_current_ = narrow;
    }
    if (!narrow) return nullptr;
    // What the run leaves in each slot it writes.
    if (zero_extended_slots_.size() < plan->written.size()) zero_extended_slots_.resize(plan->written.size(), 0);
    for (std::size_t slot = 0; slot < plan->written.size(); ++slot)
        if (plan->written[slot]) zero_extended_slots_[slot] = plan->ends_zero_extended[slot];
    return &*plan;
}

// Compiled three times, for AVX-512 (x86-64-v4: eight 64-bit lanes, and 64-bit multiplies, shifts and
// conversions in one instruction), for AVX2 and for any x86-64, and chosen at load time: the integer
// results are the same on each, only faster where the host has wider vectors (the AVX-512 clone
// takes a 256^3 shading pass from 462 to 254 ms). Only with GCC and without
// ThreadSanitizer: clang cannot link callers of a cloned member function, and the clones' load-time
// resolver runs before the TSan runtime is up.
#if defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__) && defined(__x86_64__)
#define PP5_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define PP5_VECTOR_CLONES
#endif
template <class Lane, bool Listed>
[[gnu::always_inline]] inline PpRunCounts PpArray::execute(const PpProgram& program, const PpSlotContext& context,
                                                           std::span<const int> listed,
                                                           std::span<const std::uint8_t> zero_extended) {
    // `total` PPs own backing store; `lanes` of them run (all, or the listed ones, whose fields are kept
    // in list order).
    const auto total = static_cast<std::size_t>(size());
    const std::size_t lanes = Listed ? listed.size() : total;
    const auto slots = static_cast<std::size_t>(program.storage_slots);
    auto& fields = field_storage<Lane>();
    fields.reserve(slots);  // values are kept across runs

    const auto columns = static_cast<std::size_t>(columns_);
    std::uint64_t* const store = backing_.get();
    // Lookups whose every entry fits the destination (always, from the builder) need no wrap.
    std::vector<std::uint8_t> lookup_fits(program.instructions.size(), 0);
    for (std::size_t k = 0; k < program.instructions.size(); ++k) {
        const PpInstruction& in = program.instructions[k];
        if (in.op != PpOp::Lookup) continue;
        const PpField& d = program.fields[static_cast<std::size_t>(in.dst)];
        const auto& entries = program.tables[static_cast<std::size_t>(in.table)].entries;
        lookup_fits[k] = std::all_of(entries.begin(), entries.end(),
                                     [&](std::int64_t e) { return e >= d.min_value() && e <= d.max_value(); });
    }

    PpRunCounts counts;
    counts.instructions = program.instructions.size();
    for (std::size_t first = 0; first < lanes; first += kBlockLanes) {
        const std::size_t n = std::min(kBlockLanes, lanes - first);
        // The PP that lane p of this block runs.
        const auto pp_of = [&](std::size_t p) {
            return Listed ? static_cast<std::size_t>(listed[first + p]) : first + p;
        };
        // Listed lanes' columns and rows, for the QEE, found once per block.
        std::array<std::uint32_t, Listed ? kBlockLanes : 0> lane_x{}, lane_y{};
        if constexpr (Listed) {
            for (std::size_t p = 0; p < n; ++p) {
                lane_x[p] = static_cast<std::uint32_t>(pp_of(p) % columns);
                lane_y[p] = static_cast<std::uint32_t>(pp_of(p) / columns);
            }
        }
        auto field = [&](int id) {
            return fields.slot(static_cast<std::size_t>(program.fields[static_cast<std::size_t>(id)].storage)) + first;
        };
        std::uint8_t* en = enabled_.data() + first;
        std::fill(en, en + n, std::uint8_t{1});
        std::uint64_t enabled_count = n;

        for (std::size_t k = 0; k < program.instructions.size(); ++k) {
            const PpInstruction& in = program.instructions[k];
            counts.pp_operations += n;
            counts.enabled_pp_operations += enabled_count;
            // Where no PP of the block is enabled, every instruction but EnableAll leaves it as it is:
            // the hardware spends the cycles (counted above), the host need not.
            if (enabled_count == 0 && in.op != PpOp::EnableAll) continue;
            Lane* dst = in.dst >= 0 ? field(in.dst) : nullptr;
            const Lane* a = in.a >= 0 ? field(in.a) : nullptr;
            const Lane* b = in.b >= 0 ? field(in.b) : nullptr;
            const std::int64_t imm = in.imm;
            const Lane imm_lane = to_lane<Lane>(imm);  // imm modulo 2^lane bits
            const int shift = in.shift;
            const PpField* dst_field = in.dst >= 0 ? &program.fields[static_cast<std::size_t>(in.dst)] : nullptr;
            const Wrap<Lane> wrap = dst_field != nullptr ? Wrap<Lane>(*dst_field) : Wrap<Lane>(PpField{0, 0, 1, false});
            const bool all = enabled_count == n;
            // Operands widened to 64 bits, for results whose high bits matter: sign-extended, or
            // zero-extended for a 32-bit unsigned field (whose 32-bit lane holds its value's bits).
            const auto extension = [&](int id) {
                return !zero_extended.empty() && zero_extended[static_cast<std::size_t>(id)] ? std::int64_t{0xFFFFFFFF}
                                                                                             : std::int64_t{-1};
            };
            const std::int64_t a_bits = in.a >= 0 ? extension(in.a) : -1;
            const std::int64_t b_bits = in.b >= 0 ? extension(in.b) : -1;
            const bool a_zero_extended = a_bits != -1;
            const auto widen = [](Lane v, std::int64_t bits) {
                if constexpr (sizeof(Lane) == sizeof(std::int64_t)) return static_cast<std::int64_t>(v);
                else return static_cast<std::int64_t>(v) & bits;
            };
            const auto wide = [&](Lane v) { return widen(v, a_bits); };
            const auto wide_b = [&](Lane v) { return widen(v, b_bits); };
            // Each case is one plain loop over the PPs; a disabled PP keeps its value. Every result is
            // wrapped to its field's width (a no-op for the widths the builder infers).
            switch (in.op) {
                case PpOp::SetConst: for_enabled(n, en, all, dst, wrap, [&](std::size_t) { return imm_lane; }); break;
                case PpOp::Move: {
                    // A shift past the lane's width leaves its sign, as it would of the value widened.
                    const int lane_shift = std::min(shift, kLaneBits<Lane> - 1);
                    if (a_zero_extended) {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return wide(a[p]) >> shift; });
                    } else {
                        for_enabled(n, en, all, dst, wrap,
                                    [&](std::size_t p) { return static_cast<Lane>(a[p] >> lane_shift); });
                    }
                    break;
                }
                case PpOp::Add:
                    for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return add_lanes(a[p], b[p]); });
                    break;
                case PpOp::Sub:
                    for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return sub_lanes(a[p], b[p]); });
                    break;
                case PpOp::AddConst:
                    for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return add_lanes(a[p], imm_lane); });
                    break;
                case PpOp::AbsDiffConst:
                    if (lane_holds<Lane>(imm) && !a_zero_extended) {
                        // a and imm are values of the lane type, so a >= imm says the difference's sign,
                        // and the lane's low bits of |a - imm| (all the wrap keeps) are those of the
                        // difference taken the right way round.
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) {
                            return a[p] >= imm_lane ? sub_lanes(a[p], imm_lane) : sub_lanes(imm_lane, a[p]);
                        });
                    } else {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) {
                            const std::int64_t d = sub_lanes(wide(a[p]), imm);
                            return d < 0 ? sub_lanes<std::int64_t>(0, d) : d;
                        });
                    }
                    break;
                case PpOp::MinConst:
                    if (lane_holds<Lane>(imm) && !a_zero_extended) {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return std::min(a[p], imm_lane); });
                    } else {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return std::min(wide(a[p]), imm); });
                    }
                    break;
                case PpOp::MaxConst:
                    if (lane_holds<Lane>(imm) && !a_zero_extended) {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return std::max(a[p], imm_lane); });
                    } else {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return std::max(wide(a[p]), imm); });
                    }
                    break;
                case PpOp::Mul:
                    // Unshifted, the lane's low bits of the product are all the wrap keeps.
                    if (shift == 0) {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return mul_lanes(a[p], b[p]); });
                    } else {
                        for_enabled(n, en, all, dst, wrap,
                                    [&](std::size_t p) { return mul_lanes(wide(a[p]), wide_b(b[p])) >> shift; });
                    }
                    break;
                case PpOp::MulConst:
                    if (shift == 0) {
                        for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return mul_lanes(a[p], imm_lane); });
                    } else {
                        for_enabled(n, en, all, dst, wrap,
                                    [&](std::size_t p) { return mul_lanes(wide(a[p]), imm) >> shift; });
                    }
                    break;
                case PpOp::Div:
                    divide_block(n, en, enabled_count, dst, a, b, wide, wide_b, shift, dst_field->max_value());
                    break;
                case PpOp::Sqrt:
                    for_enabled(n, en, all, dst, wrap, [&](std::size_t p) { return isqrt_branch_free(wide(a[p])); });
                    break;
                case PpOp::Lookup: {
                    const auto& entries = program.tables[static_cast<std::size_t>(in.table)].entries;
                    const std::int64_t* table = entries.data();
                    const auto last = static_cast<std::uint64_t>(entries.size() - 1);  // a power of two, minus one
                    if (lookup_fits[k]) lookup_loop(n, en, all, dst, NoWrap(), a, table, last);
                    else lookup_loop(n, en, all, dst, wrap, a, table, last);
                    break;
                }
                case PpOp::Qee: {
                    // Row by row: A x^2 + (B y + D) x + (C y^2 + E y + F), in uint64 so that large
                    // coefficients wrap rather than overflow; exact whenever the value fits 64 bits.
                    const QeeCoefficients& q = context.expressions[static_cast<std::size_t>(in.expression)];
                    const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v); };
                    if constexpr (Listed) {
                        for (std::size_t p = 0; p < n; ++p) {
                            const std::uint64_t x = lane_x[p];
                            const std::uint64_t y = lane_y[p];
                            const auto v = static_cast<std::int64_t>(u(q.a) * x * x + u(q.b) * x * y + u(q.c) * y * y +
                                                                     u(q.d) * x + u(q.e) * y + u(q.f)) >>
                                           shift;
                            dst[p] = en[p] ? wrap(static_cast<Lane>(v)) : dst[p];
                        }
                        break;
                    }
                    std::size_t p = 0;
                    while (p < n) {
                        const std::size_t index = first + p;
                        const std::size_t y = index / columns;
                        const std::size_t x0 = index % columns;
                        const std::size_t count = std::min(columns - x0, n - p);
                        const std::uint64_t uy = y;
                        const std::uint64_t linear = u(q.b) * uy + u(q.d);
                        const std::uint64_t constant = u(q.c) * uy * uy + u(q.e) * uy + u(q.f);
                        for (std::size_t i = 0; i < count; ++i) {
                            const std::uint64_t x = x0 + i;
                            const auto v = static_cast<std::int64_t>(u(q.a) * x * x + linear * x + constant) >> shift;
                            dst[p + i] = en[p + i] ? wrap(static_cast<Lane>(v)) : dst[p + i];
                        }
                        p += count;
                    }
                    break;
                }
                case PpOp::EnableAll:
                    std::fill(en, en + n, std::uint8_t{1});
                    enabled_count = n;
                    break;
                case PpOp::EnableIf:
                    if (a_zero_extended) {
                        // Compared as the 64-bit values the lanes stand for.
                        std::array<std::int64_t, kBlockLanes> values;
                        for (std::size_t p = 0; p < n; ++p) values[p] = wide(a[p]);
                        enabled_count = enable_where(n, en, values.data(), in.compare, imm);
                    } else {
                        enabled_count = enable_where(n, en, a, in.compare, imm);
                    }
                    break;
                case PpOp::Load: {
                    // dst.bits bits at record_base_bit + record_offset; sign-extended by the wrap when signed.
                    const PpBitWindow window(context.record_base_bit + in.record_offset, dst_field->bits);
                    for_enabled(n, en, all, dst, wrap,
                                [&](std::size_t p) { return static_cast<Lane>(window.read(store, total, pp_of(p))); });
                    break;
                }
                case PpOp::Store: {
                    // The low a.bits bits of a; a disabled PP's backing store is left as it was.
                    const PpBitWindow window(context.record_base_bit + in.record_offset,
                                             program.fields[static_cast<std::size_t>(in.a)].bits);
                    const auto bits_of = [&](std::size_t p) {
                        return static_cast<std::uint64_t>(wide(a[p])) & window.mask;
                    };
                    if constexpr (Listed) {
                        for (std::size_t p = 0; p < n; ++p)
                            if (en[p]) window.write(store, total, pp_of(p), bits_of(p));
                        break;
                    }
                    std::uint64_t* low = store + static_cast<std::size_t>(window.word) * total + first;
                    const std::uint64_t low_mask = window.mask << window.shift;
                    for (std::size_t p = 0; p < n; ++p) {
                        const std::uint64_t merged = (low[p] & ~low_mask) | (bits_of(p) << window.shift);
                        low[p] = en[p] ? merged : low[p];
                    }
                    if (window.straddles()) {
                        std::uint64_t* high = low + total;
                        const std::uint64_t high_mask = window.high_mask();
                        const int down = 64 - window.shift;
                        for (std::size_t p = 0; p < n; ++p) {
                            const std::uint64_t merged = (high[p] & ~high_mask) | (bits_of(p) >> down);
                            high[p] = en[p] ? merged : high[p];
                        }
                    }
                    break;
                }
            }
        }
    }
    return counts;
}

PP5_VECTOR_CLONES
PpRunCounts PpArray::run(const PpProgram& program, const PpSlotContext& context) {
    check_runnable(program, context, local_memory_bits_, backing_store_bits_);
    const std::optional<PpNarrowPlan> plan = narrow_plan(program);
    if (const PpNarrowPlan* narrow = choose_narrow_lanes(plan))
        return execute<std::int32_t, false>(program, context, {}, narrow->zero_extended);
    return execute<std::int64_t, false>(program, context, {}, {});
}

PP5_VECTOR_CLONES
PpRunCounts PpArray::run_candidates(const PpProgram& program, const PpSlotContext& context,
                                    std::span<const int> candidates) {
    check_runnable(program, context, local_memory_bits_, backing_store_bits_);
    const PpBystander bystander = bystander_of(program);
    if (bystander.stores) {
        throw std::invalid_argument(fmt::format(
            "PP program {}: a PP its tests rule out would still store, so it cannot run on candidates alone",
            program.name));
    }
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (candidates[i] < 0 || candidates[i] >= size() || (i > 0 && candidates[i] <= candidates[i - 1])) {
            throw std::invalid_argument(
                fmt::format("PP program {}: candidate {} is PP {}; candidates must be "
                            "distinct PPs of the {}, in ascending order",
                            program.name, i, candidates[i], size()));
        }
    }
    std::optional<PpNarrowPlan> plan = narrow_plan(program);
    // A listed run writes only the candidates' lanes, so a slot could end holding 32-bit unsigned bits
    // in some lanes and not in others: such runs keep to fields read with sign extension.
    const auto any = [](const std::vector<std::uint8_t>& flags) {
        return std::any_of(flags.begin(), flags.end(), [](std::uint8_t f) { return f != 0; });
    };
    if (plan && (any(plan->zero_extended) || any(zero_extended_slots_))) plan.reset();
    const PpNarrowPlan* narrow = choose_narrow_lanes(plan);
    PpRunCounts counts = narrow != nullptr
                             ? execute<std::int32_t, true>(program, context, candidates, narrow->zero_extended)
                             : execute<std::int64_t, true>(program, context, candidates, {});
    const auto bystanders = static_cast<std::uint64_t>(size()) - candidates.size();
    counts.pp_operations += bystanders * program.instructions.size();
    counts.enabled_pp_operations += bystanders * bystander.enabled_operations;
    return counts;
}

}  // namespace pp5
