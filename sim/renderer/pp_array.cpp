#include "sim/renderer/pp_array.h"

#include "sim/renderer/pp_integer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pp5 {

namespace {

// Two's-complement wrap of a value to a field's width: what bit-serial hardware leaves in `bits` bits.
struct Wrap {
    int unused_high_bits;
    bool is_signed;
    std::uint64_t mask;

    explicit Wrap(const PpField& f)
        : unused_high_bits(64 - f.bits), is_signed(f.is_signed), mask(f.bits >= 64 ? ~0ull : (1ull << f.bits) - 1) {}
    std::int64_t operator()(std::int64_t v) const {
        if (is_signed) return static_cast<std::int64_t>(static_cast<std::uint64_t>(v) << unused_high_bits) >> unused_high_bits;
        return static_cast<std::int64_t>(static_cast<std::uint64_t>(v) & mask);
    }
};

// floor(a / b) for a >= 0, b > 0: a double estimate, corrected (exact for the fields' widths).
std::int64_t exact_quotient(std::int64_t a, std::int64_t b) {
    if (a >= (std::int64_t{1} << 52)) return a / b;
    auto q = static_cast<std::int64_t>(static_cast<double>(a) / static_cast<double>(b));
    if (q * b > a) --q;
    else if ((q + 1) * b <= a) ++q;
    return q;
}


// Arithmetic in uint64, where overflow is defined: a PP that is disabled may hold a stale value from
// an earlier program, and its (discarded) result must not be undefined behaviour.
std::int64_t add64(std::int64_t a, std::int64_t b) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b)); }
std::int64_t sub64(std::int64_t a, std::int64_t b) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) - static_cast<std::uint64_t>(b)); }
std::int64_t mul64(std::int64_t a, std::int64_t b) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b)); }

// A bit range of every PP's backing store, the same for all PPs of a run: where it starts, which
// word it is in, and whether it spills into the next.
struct BitWindow {
    int word;
    int shift;
    int bits;
    std::uint64_t mask;

    BitWindow(int offset, int width, int store_bits, const char* what)
        : word(offset / 64), shift(offset % 64), bits(width), mask(width >= 64 ? ~0ull : (1ull << width) - 1) {
        if (offset < 0 || offset + width > store_bits) {
            throw std::invalid_argument(fmt::format("PP program {} of {} bits at {} is past the {}-bit backing store", what,
                                                    width, offset, store_bits));
        }
    }
    // The store is word-major (word w of PP p at store[w * pps + p]), so one window over all PPs
    // reads memory in order.
    std::uint64_t read(const std::uint64_t* store, std::size_t pps, std::size_t p) const {
        const std::uint64_t* low = store + static_cast<std::size_t>(word) * pps + p;
        std::uint64_t v = *low >> shift;
        if (shift + bits > 64) v |= low[pps] << (64 - shift);
        return v & mask;
    }
    void write(std::uint64_t* store, std::size_t pps, std::size_t p, std::uint64_t value) const {
        std::uint64_t* low = store + static_cast<std::size_t>(word) * pps + p;
        value &= mask;
        *low = (*low & ~(mask << shift)) | (value << shift);
        if (shift + bits > 64) {
            const std::uint64_t high_mask = (1ull << (shift + bits - 64)) - 1;
            low[pps] = (low[pps] & ~high_mask) | (value >> (64 - shift));
        }
    }
};

// dst[p] = value(p) on every enabled PP; a disabled PP keeps its value. The all-enabled case is a
// plain loop the compiler can vectorise.
template <class Value>
[[gnu::always_inline]] inline void for_enabled(std::size_t n, const std::uint8_t* enabled, bool all, std::int64_t* dst, Value&& value) {
    if (all) {
        for (std::size_t p = 0; p < n; ++p) dst[p] = value(p);
    } else {
        // A branch-free blend, so this loop vectorises too.
        for (std::size_t p = 0; p < n; ++p) {
            const std::int64_t keep = static_cast<std::int64_t>(enabled[p]) - 1;  // 0 where enabled, all ones where not
            dst[p] = (value(p) & ~keep) | (dst[p] & keep);
        }
    }
}

bool compare(std::int64_t a, PpCompare c, std::int64_t b) {
    switch (c) {
        case PpCompare::Less: return a < b;
        case PpCompare::LessEqual: return a <= b;
        case PpCompare::Equal: return a == b;
        case PpCompare::NotEqual: return a != b;
        case PpCompare::GreaterEqual: return a >= b;
        case PpCompare::Greater: return a > b;
    }
    return false;
}

}  // namespace

PpRunCounts& PpRunCounts::operator+=(const PpRunCounts& other) {
    instructions += other.instructions;
    pp_operations += other.pp_operations;
    enabled_pp_operations += other.enabled_pp_operations;
    return *this;
}

PpArray::PpArray(int columns, int rows, int local_memory_bits, int backing_store_bits)
    : columns_(columns), rows_(rows), local_memory_bits_(local_memory_bits), backing_store_bits_(backing_store_bits) {
    if (columns < 1 || rows < 1 || local_memory_bits < 1 || backing_store_bits < 0) {
        throw std::invalid_argument("PpArray: sizes must be positive");
    }
    backing_words_ = (backing_store_bits + 63) / 64;
    backing_.assign(static_cast<std::size_t>(size()) * static_cast<std::size_t>(backing_words_), 0);
    enabled_.assign(static_cast<std::size_t>(size()), 1);
}

void PpArray::write_backing(int pp, int bit_offset, int bits, std::uint64_t value) {
    check_backing_access(pp, bit_offset, bits);
    BitWindow(bit_offset, bits, backing_store_bits_, "write").write(backing_.data(), static_cast<std::size_t>(size()),
                                                                    static_cast<std::size_t>(pp), value);
}

std::uint64_t PpArray::read_backing(int pp, int bit_offset, int bits) const {
    check_backing_access(pp, bit_offset, bits);
    return BitWindow(bit_offset, bits, backing_store_bits_, "read").read(backing_.data(), static_cast<std::size_t>(size()),
                                                                         static_cast<std::size_t>(pp));
}

void PpArray::check_backing_access(int pp, int bit_offset, int bits) const {
    if (pp < 0 || pp >= size() || bits < 1 || bits > 64 || bit_offset < 0 || bit_offset + bits > backing_store_bits_) {
        throw std::out_of_range(fmt::format("PP backing store: {} bits at {} of PP {} (store of {} bits, {} PPs)", bits,
                                            bit_offset, pp, backing_store_bits_, size()));
    }
}

std::span<const std::int64_t> PpArray::field_values(const PpField& field) const {
    if (field.id < 0 || field.id >= static_cast<int>(fields_.size())) throw std::out_of_range("PpArray: no such field");
    return fields_[static_cast<std::size_t>(field.id)];
}

// Compiled twice, for AVX2 and for any x86-64, and chosen at load time: the integer results are the
// same either way, only faster where the host has wider vectors.
__attribute__((target_clones("avx2", "default")))
PpRunCounts PpArray::run(const PpProgram& program, const PpSlotContext& context) {
    if (program.local_memory_bits_used > local_memory_bits_) {
        throw std::invalid_argument(fmt::format("PP program {} needs {} bits of local memory; the PPs have {}", program.name,
                                                program.local_memory_bits_used, local_memory_bits_));
    }
    if (static_cast<int>(context.expressions.size()) < program.expressions) {
        throw std::invalid_argument(fmt::format("PP program {} evaluates {} QEE expressions; the slot gives {}", program.name,
                                                program.expressions, context.expressions.size()));
    }
    const auto total = static_cast<std::size_t>(size());
    if (fields_.size() < program.fields.size()) fields_.resize(program.fields.size());
    for (std::size_t id = 0; id < program.fields.size(); ++id) fields_[id].resize(total, 0);

    // PPs never exchange values, so the whole program can run over one block of PPs after another:
    // the same results, with each block's fields small enough to stay in the host's cache.
    constexpr std::size_t kBlock = 1024;
    PpRunCounts counts;
    for (std::size_t first = 0; first < total; first += kBlock) {
    const std::size_t n = std::min(kBlock, total - first);
    auto field = [&](int id) { return fields_[static_cast<std::size_t>(id)].data() + first; };
    std::uint8_t* en = enabled_.data() + first;
    std::fill(en, en + n, std::uint8_t{1});
    std::uint64_t enabled_count = n;

    for (const PpInstruction& in : program.instructions) {
        counts.instructions += first == 0 ? 1 : 0;
        counts.pp_operations += n;
        counts.enabled_pp_operations += enabled_count;
        std::int64_t* dst = in.dst >= 0 ? field(in.dst) : nullptr;
        const std::int64_t* a = in.a >= 0 ? field(in.a) : nullptr;
        const std::int64_t* b = in.b >= 0 ? field(in.b) : nullptr;
        const std::int64_t imm = in.imm;
        const int shift = in.shift;
        const Wrap wrap = dst != nullptr ? Wrap(program.fields[static_cast<std::size_t>(in.dst)]) : Wrap(PpField{0, 0, 48, true});
        // Each case is one plain loop over the PPs; a disabled PP keeps its value.
        const bool all = enabled_count == n;
        // The builder sizes every result for its operands' ranges, so arithmetic results are exact
        // in their fields without wrapping; only loads and the QEE take a declared width.
        switch (in.op) {
            case PpOp::SetConst:
                for_enabled(n, en, all, dst, [&](std::size_t) { return imm; });
                break;
            case PpOp::Move:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return a[p] >> shift; });
                break;
            case PpOp::Add:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return add64(a[p], b[p]); });
                break;
            case PpOp::Sub:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return sub64(a[p], b[p]); });
                break;
            case PpOp::AddConst:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return add64(a[p], imm); });
                break;
            case PpOp::AbsDiffConst:
                for_enabled(n, en, all, dst, [&](std::size_t p) {
                    const std::int64_t d = sub64(a[p], imm);
                    return d < 0 ? sub64(0, d) : d;
                });
                break;
            case PpOp::MinConst:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return std::min(a[p], imm); });
                break;
            case PpOp::MaxConst:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return std::max(a[p], imm); });
                break;
            case PpOp::Mul:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return mul64(a[p], b[p]) >> shift; });
                break;
            case PpOp::MulConst:
                for_enabled(n, en, all, dst, [&](std::size_t p) { return mul64(a[p], imm) >> shift; });
                break;
            case PpOp::Div: {
                const PpField& d = program.fields[static_cast<std::size_t>(in.dst)];
                const std::int64_t top = d.max_value();
                for (std::size_t p = 0; p < n; ++p) {
                    if (!en[p]) continue;
                    const std::int64_t divisor = b[p];
                    const std::int64_t dividend = static_cast<std::int64_t>(static_cast<std::uint64_t>(a[p]) << shift);
                    if (divisor <= 0 || dividend < 0) {
                        dst[p] = top;
                        continue;
                    }
                    dst[p] = std::min(exact_quotient(dividend, divisor), top);
                }
                break;
            }
            case PpOp::Sqrt:
                for (std::size_t p = 0; p < n; ++p)
                    if (en[p]) dst[p] = pp_isqrt(a[p]);
                break;
            case PpOp::Lookup: {
                const auto& entries = program.tables[static_cast<std::size_t>(in.table)].entries;
                const std::int64_t* table = entries.data();
                const auto last = static_cast<std::uint64_t>(entries.size() - 1);  // entries: a power of two
                for_enabled(n, en, all, dst, [&](std::size_t p) { return table[static_cast<std::uint64_t>(a[p]) & last]; });
                break;
            }
            case PpOp::Qee: {
                const QeeCoefficients& q = context.expressions[static_cast<std::size_t>(in.expression)];
                const auto columns = static_cast<std::size_t>(columns_);
                for (std::size_t p = 0; p < n; ++p) {
                    const auto x = static_cast<std::int64_t>((first + p) % columns);
                    const auto y = static_cast<std::int64_t>((first + p) / columns);
                    const std::int64_t v = q.a * x * x + q.b * x * y + q.c * y * y + q.d * x + q.e * y + q.f;  // x, y < 2^12
                    dst[p] = en[p] ? wrap(v >> shift) : dst[p];
                }
                break;
            }
            case PpOp::EnableAll:
                std::fill(en, en + n, std::uint8_t{1});
                enabled_count = n;
                break;
            case PpOp::EnableIf: {
                enabled_count = 0;
                for (std::size_t p = 0; p < n; ++p) {
                    en[p] = static_cast<std::uint8_t>(en[p] && compare(a[p], in.compare, imm));
                    enabled_count += en[p];
                }
                break;
            }
            case PpOp::Load: {
                const PpField& d = program.fields[static_cast<std::size_t>(in.dst)];
                const BitWindow window(context.record_base_bit + in.record_offset, d.bits, backing_store_bits_, "load");
                for (std::size_t p = 0; p < n; ++p) {
                    const std::int64_t v = wrap(static_cast<std::int64_t>(window.read(backing_.data(), total, first + p)));
                    dst[p] = en[p] ? v : dst[p];
                }
                break;
            }
            case PpOp::Store: {
                const PpField& source = program.fields[static_cast<std::size_t>(in.a)];
                const BitWindow window(context.record_base_bit + in.record_offset, source.bits, backing_store_bits_, "store");
                for (std::size_t p = 0; p < n; ++p) {
                    if (en[p]) window.write(backing_.data(), total, first + p, static_cast<std::uint64_t>(a[p]));
                }
                break;
            }
        }
    }
    }
    return counts;
}

}  // namespace pp5
