#pragma once
// A pixel-processor program: the instruction stream a renderer's controller broadcasts to its SIMD
// array of bit-serial PPs, over fields of each PP's local memory. A program is both executed (every PP
// at once, in exact integer arithmetic at the fields' widths: pp_array.h) and costed (each
// instruction's cycles from its operand widths: pp_cost_model.h), so a kernel's time follows from the
// operations it really performs.
//
// Fields are two's-complement bit ranges of local memory. The builder infers each result's width from
// its operands (an add of 8- and 9-bit fields gives 10 bits), so results never overflow, except where
// an instruction says it saturates (divide) or truncates (a right shift drops low bits). It allocates
// local memory as the hardware would have to, reusing freed bits, and refuses a program that does
// not fit, saying by how much.

#include <cstdint>
#include <string>
#include <vector>

namespace pp5 {

inline constexpr int kMaxPpFieldBits = 48;

struct PpField {
    int id = -1;     // index into PpProgram::fields
    int offset = 0;  // first bit in local memory
    int bits = 0;    // 1..kMaxPpFieldBits
    bool is_signed = false;
    // Where the host keeps the field's values (PpArray's storage slots). Fields whose lifetimes do not
    // overlap share one, as they share local-memory bits on the PPs, so the host holds no more fields
    // than are alive at once, however long the program (a classification of a thousand contours).
    int storage = -1;

    bool valid() const { return id >= 0; }
    std::int64_t max_value() const {
        return is_signed ? (std::int64_t{1} << (bits - 1)) - 1 : (std::int64_t{1} << bits) - 1;
    }
    std::int64_t min_value() const { return is_signed ? -(std::int64_t{1} << (bits - 1)) : 0; }
};

enum class PpCompare : std::uint8_t { Less, LessEqual, Equal, NotEqual, GreaterEqual, Greater };

enum class PpOp : std::uint8_t {
    SetConst,      // dst = imm
    Move,          // dst = a >> shift (arithmetic shift: low bits dropped)
    Add,           // dst = a + b
    Sub,           // dst = a - b
    AddConst,      // dst = a + imm
    AbsDiffConst,  // dst = |a - imm|
    MinConst,      // dst = min(a, imm)
    MaxConst,      // dst = max(a, imm)
    Mul,           // dst = (a * b) >> shift
    MulConst,      // dst = (a * imm) >> shift
    Div,           // dst = (a << shift) / b, rounded towards zero; dst's maximum when b = 0 or the
                   // quotient does not fit (a bit-serial restoring divide saturates)
    Sqrt,          // dst = floor(sqrt(a)), a >= 0
    Lookup,        // dst = tables[table][a]: the controller broadcasts the table, each PP keeps its entry
    Qee,           // dst = (A x^2 + B x y + C y^2 + D x + E y + F) >> shift for the PP at column x, row y,
                   // coefficients from the slot context's expression `expression`
    EnableAll,     // every PP enabled
    EnableIf,      // enable &= (a cmp imm)
    Load,          // dst = the slot's backing-store bits [record_offset, record_offset + dst.bits)
    Store,         // the slot's backing-store bits [record_offset, ...) = a
};

std::string to_string(PpOp op);

struct PpInstruction {
    PpOp op = PpOp::SetConst;
    int dst = -1;  // field ids
    int a = -1;
    int b = -1;
    std::int64_t imm = 0;
    int shift = 0;
    PpCompare compare = PpCompare::Equal;
    int table = -1;
    int expression = -1;
    int record_offset = 0;  // Load, Store: bit offset within the slot's record
};

// A lookup table indexed by an unsigned field: one entry per index value.
struct PpTable {
    std::string name;
    std::vector<std::int64_t> entries;  // size 2^index_bits
    // Runs of equal consecutive entries: the controller broadcasts one (start, value) pair per run and
    // each PP whose index is at or past the start takes the value, so the cost grows with runs.
    int runs() const;
};

struct PpProgram {
    std::string name;
    std::vector<PpField> fields;           // by id
    std::vector<std::string> field_names;  // by id
    std::vector<PpInstruction> instructions;
    std::vector<PpTable> tables;
    int expressions = 0;             // QEE expressions a slot context must supply
    int local_memory_bits_used = 0;  // the peak of simultaneously allocated bits
    int storage_slots = 0;           // host storage slots its fields use (PpField::storage)
};

class PpProgramBuilder {
public:
    // `local_memory_bits`: what each PP has. `machine_field`: the configuration key that sets it, for
    // the error when a program does not fit.
    PpProgramBuilder(std::string name, int local_memory_bits, std::string machine_field = "renderer.local_memory_bits");

    // A field of `bits` bits at the lowest free offset. Refuses machine_field (reject_field: "program P
    // needs N bits of local memory for F; the PP has M (K short)") when they are not free.
    PpField alloc(const std::string& name, int bits, bool is_signed);
    // Returns the field's bits to the free pool; its value must not be used again.
    void release(PpField field);

    PpField set_const(const std::string& name, std::int64_t value);  // width of value
    PpField set_const(const std::string& name, std::int64_t value, int bits, bool is_signed);
    PpField move(const std::string& name, PpField a, int shift = 0);
    PpField add(const std::string& name, PpField a, PpField b);
    // A running sum: `term` itself while `sum` is not yet valid, else sum + term with both released.
    PpField accumulate(const std::string& name, PpField sum, PpField term);
    PpField sub(const std::string& name, PpField a, PpField b);
    PpField add_const(const std::string& name, PpField a, std::int64_t imm);
    PpField abs_diff_const(const std::string& name, PpField a, std::int64_t imm);
    PpField min_const(const std::string& name, PpField a, std::int64_t imm);
    PpField max_const(const std::string& name, PpField a, std::int64_t imm);
    PpField mul(const std::string& name, PpField a, PpField b, int shift = 0);
    PpField mul_const(const std::string& name, PpField a, std::int64_t imm, int shift = 0);
    // Quotient of (a << shift) / b in `bits` unsigned bits; a and b must be non-negative.
    PpField div(const std::string& name, PpField a, PpField b, int shift, int bits);
    PpField sqrt(const std::string& name, PpField a);
    PpField lookup(const std::string& name, PpField index, PpTable table, int bits, bool is_signed);
    // One QEE evaluation per PP: the value of expression `expression` of the slot, in `bits` bits.
    PpField qee(const std::string& name, int expression, int bits, bool is_signed, int shift);
    void enable_all();
    void enable_if(PpField a, PpCompare compare, std::int64_t imm);
    PpField load(const std::string& name, int record_offset, int bits, bool is_signed);
    void store(PpField a, int record_offset);
    // The same into a record field of `record_bits` bits, filling all of them: a narrower non-negative
    // field is widened with zeros first (else an earlier value's high bits would stay), and a wider
    // one, which would spill into the next record field, is refused (std::invalid_argument).
    void store(PpField a, int record_offset, int record_bits);

    // Writes `value` into an existing field under the current enable mask (a conditional update).
    void assign(PpField dst, PpField value);
    void assign_const(PpField dst, std::int64_t value);

    PpProgram finish();

private:
    struct Range {
        std::int64_t lo = 0;
        std::int64_t hi = 0;
    };

    PpField result(const std::string& name, std::int64_t lo, std::int64_t hi);
    PpField emit(PpInstruction instruction, const std::string& name, std::int64_t lo, std::int64_t hi);
    void check_live(const PpField& field) const;
    std::int64_t lo(const PpField& f) const;
    std::int64_t hi(const PpField& f) const;

    PpProgram program_;
    int capacity_bits_;
    std::string machine_field_;
    std::vector<bool> used_;         // per bit of local memory
    std::vector<bool> live_;         // per field id
    std::vector<int> free_storage_;  // host storage slots of released fields, for the next fields
    std::vector<Range> ranges_;      // per field id: the values it may hold
};

// A bystander of a program is a PP that fails the first EnableIf after the program starts and after
// every EnableAll: the program's tests rule it out as soon as they look at it (a voxel far from the
// polygon being scan-converted, say). The hardware still runs every instruction on it; what it does
// while enabled is this, the same for every bystander, so the host need not run it
// (PpArray::run_candidates).
struct PpBystander {
    std::uint64_t enabled_operations = 0;  // instructions that find it enabled
    bool stores = false;                   // whether it stores while enabled (then it must be run)
};
PpBystander bystander_of(const PpProgram& program);

// Bits needed to hold every value in [lo, hi] (signed when lo < 0).
int pp_bits_for_range(std::int64_t lo, std::int64_t hi);

}  // namespace pp5
