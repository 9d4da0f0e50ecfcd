#include "sim/pixel_processors/pp_program.h"

#include "sim/core/input_error.h"
#include "sim/pixel_processors/pp_integer.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pp5 {

namespace {

std::int64_t floor_shift(std::int64_t x, int shift) { return x >> shift; }  // arithmetic: floor

std::string plural_bits(std::int64_t n) { return fmt::format("{} bit{}", n, n == 1 ? "" : "s"); }

// Range arithmetic that refuses to overflow: a range past 64 bits could never be held by a field
// (at most kMaxPpFieldBits), so the instruction is rejected, naming the field it would have made.
class CheckedRange {
public:
    CheckedRange(const std::string& program, const std::string& field) : program_(program), field_(field) {}

    std::int64_t add(std::int64_t a, std::int64_t b) const {
        std::int64_t r = 0;
        if (__builtin_add_overflow(a, b, &r)) fail();
        return r;
    }
    std::int64_t sub(std::int64_t a, std::int64_t b) const {
        std::int64_t r = 0;
        if (__builtin_sub_overflow(a, b, &r)) fail();
        return r;
    }
    std::int64_t mul(std::int64_t a, std::int64_t b) const {
        std::int64_t r = 0;
        if (__builtin_mul_overflow(a, b, &r)) fail();
        return r;
    }
    std::int64_t abs(std::int64_t a) const {
        if (a == std::numeric_limits<std::int64_t>::min()) fail();
        return a < 0 ? -a : a;
    }

private:
    [[noreturn]] void fail() const {
        throw std::invalid_argument(
            fmt::format("PP program {}: the values of field {} would need more than 64 bits "
                        "(a field holds at most {})",
                        program_, field_, kMaxPpFieldBits));
    }

    const std::string& program_;
    const std::string& field_;
};

struct ProductRange {
    std::int64_t lo = 0;
    std::int64_t hi = 0;
};

// The range of x * y over x in [a_lo, a_hi], y in [b_lo, b_hi]: the extremes are at the corners.
ProductRange product_range(const CheckedRange& c, std::int64_t a_lo, std::int64_t a_hi, std::int64_t b_lo,
                           std::int64_t b_hi) {
    const std::int64_t corners[4] = {c.mul(a_lo, b_lo), c.mul(a_lo, b_hi), c.mul(a_hi, b_lo), c.mul(a_hi, b_hi)};
    return {*std::min_element(corners, corners + 4), *std::max_element(corners, corners + 4)};
}

}  // namespace

PpProgramBuilder::PpProgramBuilder(std::string name, int local_memory_bits, std::string machine_field)
    : capacity_bits_(local_memory_bits),
      machine_field_(std::move(machine_field)),
      used_(static_cast<std::size_t>(std::max(local_memory_bits, 0)), false) {
    program_.name = std::move(name);
}

namespace {

void check_width(const std::string& program, const std::string& field, int bits) {
    if (bits < 1 || bits > kMaxPpFieldBits) {
        throw std::invalid_argument(
            fmt::format("PP program {}: field {} of {} bits (1 to {} allowed)", program, field, bits, kMaxPpFieldBits));
    }
}

// Right shifts of a 64-bit value: 0 to 63 places.
void check_shift(const std::string& program, const std::string& field, int shift) {
    if (shift < 0 || shift > 63) {
        throw std::invalid_argument(
            fmt::format("PP program {}: field {}: shift of {} (0 to 63 allowed)", program, field, shift));
    }
}

void check_record_offset(const std::string& program, const std::string& field, int record_offset) {
    if (record_offset < 0) {
        throw std::invalid_argument(
            fmt::format("PP program {}: field {}: negative record offset {}", program, field, record_offset));
    }
}

}  // namespace

PpField PpProgramBuilder::alloc(const std::string& name, int bits, bool is_signed) {
    check_width(program_.name, name, bits);
    // First fit over the free bits.
    int offset = -1;
    for (int start = 0, run = 0; start + run < capacity_bits_;) {
        if (used_[static_cast<std::size_t>(start + run)]) {
            start += run + 1;
            run = 0;
        } else if (++run == bits) {
            offset = start;
            break;
        }
    }
    const int in_use = static_cast<int>(std::count(used_.begin(), used_.end(), true));
    if (offset < 0) {
        const int needed = in_use + bits;
        if (needed > capacity_bits_) {
            reject_field(
                machine_field_,
                fmt::format("PP program {} needs {} bits of local memory for field {}; each PP has {} ({} short)",
                            program_.name, needed, name, capacity_bits_, plural_bits(needed - capacity_bits_)));
        }
        // Enough bits are free, but released fields left them in pieces too small for this one.
        int longest = 0;
        for (int i = 0, run = 0; i < capacity_bits_; ++i) {
            run = used_[static_cast<std::size_t>(i)] ? 0 : run + 1;
            longest = std::max(longest, run);
        }
        reject_field(machine_field_,
                     fmt::format("PP program {} needs {} contiguous bits of local memory for field {}; each PP has {}, "
                                 "{} of them free but the longest free run is {} ({} short)",
                                 program_.name, bits, name, capacity_bits_, capacity_bits_ - in_use,
                                 plural_bits(longest), plural_bits(bits - longest)));
    }
    for (int i = 0; i < bits; ++i) used_[static_cast<std::size_t>(offset + i)] = true;
    program_.local_memory_bits_used = std::max(program_.local_memory_bits_used, in_use + bits);

    PpField field{static_cast<int>(program_.fields.size()), offset, bits, is_signed};
    if (free_storage_.empty()) {
        field.storage = program_.storage_slots++;
    } else {
        field.storage = free_storage_.back();
        free_storage_.pop_back();
    }
    program_.fields.push_back(field);
    program_.field_names.push_back(name);
    live_.push_back(true);
    ranges_.push_back({field.min_value(), field.max_value()});  // unknown contents: anything the width holds
    return field;
}

void PpProgramBuilder::check_live(const PpField& field) const {
    if (field.id < 0 || field.id >= static_cast<int>(program_.fields.size())) {
        throw std::invalid_argument(
            fmt::format("PP program {}: field id {} is not a field of this program", program_.name, field.id));
    }
    const auto id = static_cast<std::size_t>(field.id);
    const PpField& known = program_.fields[id];
    if (known.offset != field.offset || known.bits != field.bits || known.is_signed != field.is_signed ||
        known.storage != field.storage) {
        throw std::invalid_argument(fmt::format("PP program {}: field id {} ({}) does not match this program's field",
                                                program_.name, field.id, program_.field_names[id]));
    }
    if (!live_[id]) {
        throw std::invalid_argument(fmt::format("PP program {}: field {} (id {}) used after it was released",
                                                program_.name, program_.field_names[id], field.id));
    }
}

void PpProgramBuilder::release(PpField field) {
    check_live(field);
    live_[static_cast<std::size_t>(field.id)] = false;
    free_storage_.push_back(program_.fields[static_cast<std::size_t>(field.id)].storage);
    for (int i = 0; i < field.bits; ++i) used_[static_cast<std::size_t>(field.offset + i)] = false;
}

PpField PpProgramBuilder::result(const std::string& name, std::int64_t lo, std::int64_t hi) {
    const PpField f = alloc(name, pp_bits_for_range(lo, hi), lo < 0);
    ranges_[static_cast<std::size_t>(f.id)] = {lo, hi};
    return f;
}

PpField PpProgramBuilder::emit(PpInstruction instruction, const std::string& name, std::int64_t lo, std::int64_t hi) {
    const PpField dst = result(name, lo, hi);
    instruction.dst = dst.id;
    program_.instructions.push_back(instruction);
    return dst;
}

std::int64_t PpProgramBuilder::lo(const PpField& f) const { return ranges_[static_cast<std::size_t>(f.id)].lo; }
std::int64_t PpProgramBuilder::hi(const PpField& f) const { return ranges_[static_cast<std::size_t>(f.id)].hi; }

PpField PpProgramBuilder::set_const(const std::string& name, std::int64_t value) {
    PpInstruction i{PpOp::SetConst};
    i.imm = value;
    return emit(i, name, value, value);
}

PpField PpProgramBuilder::set_const(const std::string& name, std::int64_t value, int bits, bool is_signed) {
    check_width(program_.name, name, bits);
    const PpField shape{0, 0, bits, is_signed};
    if (value < shape.min_value() || value > shape.max_value()) {
        throw std::invalid_argument(fmt::format("PP program {}: {} does not fit field {} ({} bits, {})", program_.name,
                                                value, name, bits, is_signed ? "signed" : "unsigned"));
    }
    const PpField dst = alloc(name, bits, is_signed);
    // Later conditional writes (assign) widen the range to what they may put there.
    ranges_[static_cast<std::size_t>(dst.id)] = {value, value};
    PpInstruction i{PpOp::SetConst};
    i.dst = dst.id;
    i.imm = value;
    program_.instructions.push_back(i);
    return dst;
}

PpField PpProgramBuilder::move(const std::string& name, PpField a, int shift) {
    check_live(a);
    check_shift(program_.name, name, shift);
    PpInstruction i{PpOp::Move};
    i.a = a.id;
    i.shift = shift;
    return emit(i, name, floor_shift(lo(a), shift), floor_shift(hi(a), shift));
}

PpField PpProgramBuilder::add(const std::string& name, PpField a, PpField b) {
    check_live(a);
    check_live(b);
    const CheckedRange c(program_.name, name);
    PpInstruction i{PpOp::Add};
    i.a = a.id;
    i.b = b.id;
    return emit(i, name, c.add(lo(a), lo(b)), c.add(hi(a), hi(b)));
}

PpField PpProgramBuilder::accumulate(const std::string& name, PpField sum, PpField term) {
    if (!sum.valid()) return term;
    const PpField next = add(name, sum, term);
    release(sum);
    release(term);
    return next;
}

PpField PpProgramBuilder::sub(const std::string& name, PpField a, PpField b) {
    check_live(a);
    check_live(b);
    const CheckedRange c(program_.name, name);
    PpInstruction i{PpOp::Sub};
    i.a = a.id;
    i.b = b.id;
    if (a.id == b.id) return emit(i, name, 0, 0);  // x - x
    return emit(i, name, c.sub(lo(a), hi(b)), c.sub(hi(a), lo(b)));
}

PpField PpProgramBuilder::add_const(const std::string& name, PpField a, std::int64_t imm) {
    check_live(a);
    const CheckedRange c(program_.name, name);
    PpInstruction i{PpOp::AddConst};
    i.a = a.id;
    i.imm = imm;
    return emit(i, name, c.add(lo(a), imm), c.add(hi(a), imm));
}

PpField PpProgramBuilder::abs_diff_const(const std::string& name, PpField a, std::int64_t imm) {
    check_live(a);
    const CheckedRange c(program_.name, name);
    PpInstruction i{PpOp::AbsDiffConst};
    i.a = a.id;
    i.imm = imm;
    const std::int64_t d1 = c.sub(lo(a), imm);
    const std::int64_t d2 = c.sub(hi(a), imm);
    const std::int64_t top = std::max(c.abs(d1), c.abs(d2));
    const std::int64_t bottom = (d1 <= 0 && d2 >= 0) ? 0 : std::min(c.abs(d1), c.abs(d2));
    return emit(i, name, bottom, top);
}

PpField PpProgramBuilder::min_const(const std::string& name, PpField a, std::int64_t imm) {
    check_live(a);
    PpInstruction i{PpOp::MinConst};
    i.a = a.id;
    i.imm = imm;
    return emit(i, name, std::min(lo(a), imm), std::min(hi(a), imm));
}

PpField PpProgramBuilder::max_const(const std::string& name, PpField a, std::int64_t imm) {
    check_live(a);
    PpInstruction i{PpOp::MaxConst};
    i.a = a.id;
    i.imm = imm;
    return emit(i, name, std::max(lo(a), imm), std::max(hi(a), imm));
}

PpField PpProgramBuilder::mul(const std::string& name, PpField a, PpField b, int shift) {
    check_live(a);
    check_live(b);
    check_shift(program_.name, name, shift);
    const CheckedRange c(program_.name, name);
    PpInstruction i{PpOp::Mul};
    i.a = a.id;
    i.b = b.id;
    i.shift = shift;
    ProductRange r = product_range(c, lo(a), hi(a), lo(b), hi(b));
    if (a.id == b.id) {  // a square is never negative
        const std::int64_t l = c.mul(lo(a), lo(a));
        const std::int64_t h = c.mul(hi(a), hi(a));
        r = {(lo(a) <= 0 && hi(a) >= 0) ? 0 : std::min(l, h), std::max(l, h)};
    }
    return emit(i, name, floor_shift(r.lo, shift), floor_shift(r.hi, shift));
}

PpField PpProgramBuilder::mul_const(const std::string& name, PpField a, std::int64_t imm, int shift) {
    check_live(a);
    check_shift(program_.name, name, shift);
    const CheckedRange c(program_.name, name);
    PpInstruction i{PpOp::MulConst};
    i.a = a.id;
    i.imm = imm;
    i.shift = shift;
    const ProductRange r = product_range(c, lo(a), hi(a), imm, imm);
    return emit(i, name, floor_shift(r.lo, shift), floor_shift(r.hi, shift));
}

PpField PpProgramBuilder::div(const std::string& name, PpField a, PpField b, int shift, int bits) {
    check_live(a);
    check_live(b);
    check_width(program_.name, name, bits);
    if (lo(a) < 0 || lo(b) < 0) {
        throw std::invalid_argument(
            fmt::format("PP program {}: divide {} = {} / {}: operands may be negative "
                        "(ranges [{}, {}] and [{}, {}])",
                        program_.name, name, program_.field_names[static_cast<std::size_t>(a.id)],
                        program_.field_names[static_cast<std::size_t>(b.id)], lo(a), hi(a), lo(b), hi(b)));
    }
    // The dividend a << shift must fit 63 bits.
    if (shift < 0 || shift > 62 || hi(a) > (std::numeric_limits<std::int64_t>::max() >> shift)) {
        throw std::invalid_argument(
            fmt::format("PP program {}: divide {}: dividend up to {} shifted by {} does not fit 63 bits", program_.name,
                        name, hi(a), shift));
    }
    PpInstruction i{PpOp::Div};
    i.a = a.id;
    i.b = b.id;
    i.shift = shift;
    const PpField dst = alloc(name, bits, false);  // range [0, 2^bits - 1]: it saturates
    i.dst = dst.id;
    program_.instructions.push_back(i);
    return dst;
}

PpField PpProgramBuilder::sqrt(const std::string& name, PpField a) {
    check_live(a);
    PpInstruction i{PpOp::Sqrt};
    i.a = a.id;
    return emit(i, name, pp_isqrt(std::max<std::int64_t>(lo(a), 0)), pp_isqrt(std::max<std::int64_t>(hi(a), 0)));
}

PpField PpProgramBuilder::lookup(const std::string& name, PpField index, PpTable table, int bits, bool is_signed) {
    check_live(index);
    check_width(program_.name, name, bits);
    if (index.is_signed) {
        throw std::invalid_argument(fmt::format("PP program {}: table {} indexed by signed field {}", program_.name,
                                                table.name, program_.field_names[static_cast<std::size_t>(index.id)]));
    }
    if (index.bits > 30 || table.entries.size() != (std::size_t{1} << index.bits)) {
        throw std::invalid_argument(fmt::format("PP program {}: table {} has {} entries; a {}-bit index needs 2^{}",
                                                program_.name, table.name, table.entries.size(), index.bits,
                                                index.bits));
    }
    const PpField shape{0, 0, bits, is_signed};
    for (std::size_t k = 0; k < table.entries.size(); ++k) {
        const std::int64_t e = table.entries[k];
        if (e < shape.min_value() || e > shape.max_value()) {
            throw std::invalid_argument(
                fmt::format("PP program {}: table {} entry {} = {} does not fit {} ({} bits, {})", program_.name,
                            table.name, k, e, name, bits, is_signed ? "signed" : "unsigned"));
        }
    }
    const PpField dst = alloc(name, bits, is_signed);
    ranges_[static_cast<std::size_t>(dst.id)] = {*std::min_element(table.entries.begin(), table.entries.end()),
                                                 *std::max_element(table.entries.begin(), table.entries.end())};
    PpInstruction i{PpOp::Lookup};
    i.a = index.id;
    i.dst = dst.id;
    i.table = static_cast<int>(program_.tables.size());
    program_.tables.push_back(std::move(table));
    program_.instructions.push_back(i);
    return dst;
}

PpField PpProgramBuilder::qee(const std::string& name, int expression, int bits, bool is_signed, int shift) {
    if (expression < 0) {
        throw std::invalid_argument(
            fmt::format("PP program {}: field {}: QEE expression {}", program_.name, name, expression));
    }
    check_shift(program_.name, name, shift);
    PpInstruction i{PpOp::Qee};
    i.expression = expression;
    i.shift = shift;
    const PpField dst = alloc(name, bits, is_signed);  // the declared width: values past it wrap
    i.dst = dst.id;
    program_.instructions.push_back(i);
    program_.expressions = std::max(program_.expressions, expression + 1);
    return dst;
}

void PpProgramBuilder::enable_all() { program_.instructions.push_back(PpInstruction{PpOp::EnableAll}); }

void PpProgramBuilder::enable_if(PpField a, PpCompare compare, std::int64_t imm) {
    check_live(a);
    PpInstruction i{PpOp::EnableIf};
    i.a = a.id;
    i.compare = compare;
    i.imm = imm;
    program_.instructions.push_back(i);
}

PpField PpProgramBuilder::load(const std::string& name, int record_offset, int bits, bool is_signed) {
    check_record_offset(program_.name, name, record_offset);
    PpInstruction i{PpOp::Load};
    i.record_offset = record_offset;
    const PpField dst = alloc(name, bits, is_signed);
    i.dst = dst.id;
    program_.instructions.push_back(i);
    return dst;
}

void PpProgramBuilder::store(PpField a, int record_offset) {
    check_live(a);
    check_record_offset(program_.name, program_.field_names[static_cast<std::size_t>(a.id)], record_offset);
    PpInstruction i{PpOp::Store};
    i.a = a.id;
    i.record_offset = record_offset;
    program_.instructions.push_back(i);
}

void PpProgramBuilder::store(PpField a, int record_offset, int record_bits) {
    check_live(a);
    const std::string& name = program_.field_names[static_cast<std::size_t>(a.id)];
    if (a.bits > record_bits) {
        throw std::invalid_argument(fmt::format("PP program {}: {} is {} bits wide, the record field at {} only {}",
                                                program_.name, name, a.bits, record_offset, record_bits));
    }
    if (a.bits == record_bits) {
        store(a, record_offset);
        return;
    }
    // Narrower: widen with zeros first, so that no bit of an earlier value stays behind.
    if (lo(a) < 0) {
        throw std::invalid_argument(
            fmt::format("PP program {}: {} may be negative; it cannot fill the {}-bit record field at {}",
                        program_.name, name, record_bits, record_offset));
    }
    const PpField wide = alloc(name + " widened", record_bits, false);
    assign(wide, a);
    store(wide, record_offset);
    release(wide);
}

void PpProgramBuilder::assign(PpField dst, PpField value) {
    check_live(dst);
    check_live(value);
    if (lo(value) < dst.min_value() || hi(value) > dst.max_value()) {
        throw std::invalid_argument(fmt::format(
            "PP program {}: {} (values [{}, {}]) may not fit {} ({} bits, {})", program_.name,
            program_.field_names[static_cast<std::size_t>(value.id)], lo(value), hi(value),
            program_.field_names[static_cast<std::size_t>(dst.id)], dst.bits, dst.is_signed ? "signed" : "unsigned"));
    }
    Range& r = ranges_[static_cast<std::size_t>(dst.id)];
    r = {std::min(r.lo, lo(value)), std::max(r.hi, hi(value))};
    PpInstruction i{PpOp::Move};
    i.a = value.id;
    i.dst = dst.id;
    program_.instructions.push_back(i);
}

void PpProgramBuilder::assign_const(PpField dst, std::int64_t value) {
    check_live(dst);
    if (value < dst.min_value() || value > dst.max_value()) {
        throw std::invalid_argument(fmt::format("PP program {}: {} does not fit {} ({} bits, {})", program_.name, value,
                                                program_.field_names[static_cast<std::size_t>(dst.id)], dst.bits,
                                                dst.is_signed ? "signed" : "unsigned"));
    }
    Range& r = ranges_[static_cast<std::size_t>(dst.id)];
    r = {std::min(r.lo, value), std::max(r.hi, value)};
    PpInstruction i{PpOp::SetConst};
    i.dst = dst.id;
    i.imm = value;
    program_.instructions.push_back(i);
}

PpProgram PpProgramBuilder::finish() { return std::move(program_); }

}  // namespace pp5
