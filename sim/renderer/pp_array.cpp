#include "sim/renderer/pp_array.h"

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

std::int64_t exact_isqrt(std::int64_t x) {
    if (x <= 0) return 0;
    auto r = static_cast<std::int64_t>(std::sqrt(static_cast<double>(x)));
    while (r * r > x) --r;
    while ((r + 1) * (r + 1) <= x) ++r;
    return r;
}

// Arithmetic in uint64, where overflow is defined: a PP that is disabled may hold a stale value from
// an earlier program, and its (discarded) result must not be undefined behaviour.
std::int64_t add64(std::int64_t a, std::int64_t b) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b)); }
std::int64_t sub64(std::int64_t a, std::int64_t b) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) - static_cast<std::uint64_t>(b)); }
std::int64_t mul64(std::int64_t a, std::int64_t b) { return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b)); }

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
    if (pp < 0 || pp >= size() || bits < 1 || bits > 64 || bit_offset < 0 || bit_offset + bits > backing_store_bits_) {
        throw std::out_of_range(fmt::format("PP backing store: {} bits at {} of PP {} (store of {} bits, {} PPs)", bits,
                                            bit_offset, pp, backing_store_bits_, size()));
    }
    std::uint64_t* words = backing_.data() + static_cast<std::size_t>(pp) * static_cast<std::size_t>(backing_words_);
    const int word = bit_offset / 64;
    const int shift = bit_offset % 64;
    const std::uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
    value &= mask;
    words[word] = (words[word] & ~(mask << shift)) | (value << shift);
    if (shift + bits > 64) {
        const int spill = shift + bits - 64;
        const std::uint64_t high_mask = (1ull << spill) - 1;
        words[word + 1] = (words[word + 1] & ~high_mask) | (value >> (64 - shift));
    }
}

std::uint64_t PpArray::read_backing(int pp, int bit_offset, int bits) const {
    if (pp < 0 || pp >= size() || bits < 1 || bits > 64 || bit_offset < 0 || bit_offset + bits > backing_store_bits_) {
        throw std::out_of_range(fmt::format("PP backing store: {} bits at {} of PP {} (store of {} bits, {} PPs)", bits,
                                            bit_offset, pp, backing_store_bits_, size()));
    }
    const std::uint64_t* words = backing_.data() + static_cast<std::size_t>(pp) * static_cast<std::size_t>(backing_words_);
    const int word = bit_offset / 64;
    const int shift = bit_offset % 64;
    const std::uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
    std::uint64_t value = words[word] >> shift;
    if (shift + bits > 64) value |= words[word + 1] << (64 - shift);
    return value & mask;
}

std::span<const std::int64_t> PpArray::field_values(const PpField& field) const {
    if (field.id < 0 || field.id >= static_cast<int>(fields_.size())) throw std::out_of_range("PpArray: no such field");
    return fields_[static_cast<std::size_t>(field.id)];
}

PpRunCounts PpArray::run(const PpProgram& program, const PpSlotContext& context) {
    if (program.local_memory_bits_used > local_memory_bits_) {
        throw std::invalid_argument(fmt::format("PP program {} needs {} bits of local memory; the PPs have {}", program.name,
                                                program.local_memory_bits_used, local_memory_bits_));
    }
    if (static_cast<int>(context.expressions.size()) < program.expressions) {
        throw std::invalid_argument(fmt::format("PP program {} evaluates {} QEE expressions; the slot gives {}", program.name,
                                                program.expressions, context.expressions.size()));
    }
    const auto n = static_cast<std::size_t>(size());
    if (fields_.size() < program.fields.size()) fields_.resize(program.fields.size());
    for (std::size_t id = 0; id < program.fields.size(); ++id) fields_[id].resize(n, 0);
    std::fill(enabled_.begin(), enabled_.end(), 1);
    std::uint64_t enabled_count = n;

    PpRunCounts counts;
    auto field = [&](int id) { return fields_[static_cast<std::size_t>(id)].data(); };
    const std::uint8_t* en = enabled_.data();

    for (const PpInstruction& in : program.instructions) {
        ++counts.instructions;
        counts.pp_operations += n;
        counts.enabled_pp_operations += enabled_count;
        std::int64_t* dst = in.dst >= 0 ? field(in.dst) : nullptr;
        const std::int64_t* a = in.a >= 0 ? field(in.a) : nullptr;
        const std::int64_t* b = in.b >= 0 ? field(in.b) : nullptr;
        const std::int64_t imm = in.imm;
        const int shift = in.shift;
        const Wrap wrap = dst != nullptr ? Wrap(program.fields[static_cast<std::size_t>(in.dst)]) : Wrap(PpField{0, 0, 64, true});
        // Each case is one plain loop over the PPs; a disabled PP keeps its value.
        switch (in.op) {
            case PpOp::SetConst:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(imm) : dst[p];
                break;
            case PpOp::Move:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(a[p] >> shift) : dst[p];
                break;
            case PpOp::Add:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(add64(a[p], b[p])) : dst[p];
                break;
            case PpOp::Sub:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(sub64(a[p], b[p])) : dst[p];
                break;
            case PpOp::AddConst:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(add64(a[p], imm)) : dst[p];
                break;
            case PpOp::AbsDiffConst:
                for (std::size_t p = 0; p < n; ++p) {
                    const std::int64_t d = sub64(a[p], imm);
                    dst[p] = en[p] ? wrap(d < 0 ? sub64(0, d) : d) : dst[p];
                }
                break;
            case PpOp::MinConst:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(std::min(a[p], imm)) : dst[p];
                break;
            case PpOp::MaxConst:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(std::max(a[p], imm)) : dst[p];
                break;
            case PpOp::Mul:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(mul64(a[p], b[p]) >> shift) : dst[p];
                break;
            case PpOp::MulConst:
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? wrap(mul64(a[p], imm) >> shift) : dst[p];
                break;
            case PpOp::Div: {
                const PpField& d = program.fields[static_cast<std::size_t>(in.dst)];
                const std::int64_t top = d.max_value();
                for (std::size_t p = 0; p < n; ++p) {
                    if (!en[p]) continue;
                    const std::int64_t divisor = b[p];
                    const std::int64_t dividend = static_cast<std::int64_t>(static_cast<std::uint64_t>(a[p]) << shift);
                    dst[p] = (divisor <= 0 || dividend < 0 || dividend / divisor > top) ? top : dividend / divisor;
                }
                break;
            }
            case PpOp::Sqrt:
                for (std::size_t p = 0; p < n; ++p)
                    if (en[p]) dst[p] = wrap(exact_isqrt(a[p]));
                break;
            case PpOp::Lookup: {
                const auto& entries = program.tables[static_cast<std::size_t>(in.table)].entries;
                const std::int64_t* table = entries.data();
                const auto last = static_cast<std::uint64_t>(entries.size() - 1);  // entries: a power of two
                for (std::size_t p = 0; p < n; ++p) dst[p] = en[p] ? table[static_cast<std::uint64_t>(a[p]) & last] : dst[p];
                break;
            }
            case PpOp::Qee: {
                const QeeCoefficients& q = context.expressions[static_cast<std::size_t>(in.expression)];
                for (int row = 0; row < rows_; ++row) {
                    const std::int64_t y = row;
                    const std::size_t base = static_cast<std::size_t>(row) * static_cast<std::size_t>(columns_);
                    for (int column = 0; column < columns_; ++column) {
                        const std::int64_t x = column;
                        const std::int64_t v = q.a * x * x + q.b * x * y + q.c * y * y + q.d * x + q.e * y + q.f;  // x, y < 2^12
                        const std::size_t p = base + static_cast<std::size_t>(column);
                        dst[p] = en[p] ? wrap(v >> shift) : dst[p];
                    }
                }
                break;
            }
            case PpOp::EnableAll:
                std::fill(enabled_.begin(), enabled_.end(), 1);
                enabled_count = n;
                break;
            case PpOp::EnableIf: {
                enabled_count = 0;
                for (std::size_t p = 0; p < n; ++p) {
                    enabled_[p] = static_cast<std::uint8_t>(enabled_[p] && compare(a[p], in.compare, imm));
                    enabled_count += enabled_[p];
                }
                break;
            }
            case PpOp::Load: {
                const PpField& d = program.fields[static_cast<std::size_t>(in.dst)];
                const int offset = context.record_base_bit + in.record_offset;
                if (offset + d.bits > backing_store_bits_) throw std::invalid_argument("PP program load past the backing store");
                for (std::size_t p = 0; p < n; ++p) {
                    if (en[p]) dst[p] = wrap(static_cast<std::int64_t>(read_backing(static_cast<int>(p), offset, d.bits)));
                }
                break;
            }
            case PpOp::Store: {
                const PpField& s = program.fields[static_cast<std::size_t>(in.a)];
                const int offset = context.record_base_bit + in.record_offset;
                if (offset + s.bits > backing_store_bits_) throw std::invalid_argument("PP program store past the backing store");
                for (std::size_t p = 0; p < n; ++p) {
                    if (en[p]) write_backing(static_cast<int>(p), offset, s.bits, static_cast<std::uint64_t>(a[p]));
                }
                break;
            }
        }
    }
    return counts;
}

}  // namespace pp5
