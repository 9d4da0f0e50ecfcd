#include "sim/pixel_processors/pp_program_check.h"

#include <fmt/format.h>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace pp5 {

namespace {

struct Operands {
    bool dst, a, b;
};

// Which field operands each instruction reads or writes.
Operands operands_of(PpOp op) {
    switch (op) {
        case PpOp::SetConst:
        case PpOp::Qee:
        case PpOp::Load: return {true, false, false};
        case PpOp::Move:
        case PpOp::AddConst:
        case PpOp::AbsDiffConst:
        case PpOp::MinConst:
        case PpOp::MaxConst:
        case PpOp::MulConst:
        case PpOp::Sqrt:
        case PpOp::Lookup: return {true, true, false};
        case PpOp::Add:
        case PpOp::Sub:
        case PpOp::Mul:
        case PpOp::Div: return {true, true, true};
        case PpOp::EnableAll: return {false, false, false};
        case PpOp::EnableIf:
        case PpOp::Store: return {false, true, false};
    }
    return {false, false, false};
}

}  // namespace

void check_runnable(const PpProgram& program, const PpSlotContext& context, int local_memory_bits,
                    int backing_store_bits) {
    const auto fail = [&](const std::string& why) {
        throw std::invalid_argument(fmt::format("PP program {}: {}", program.name, why));
    };
    if (program.local_memory_bits_used > local_memory_bits) {
        fail(fmt::format("needs {} bits of local memory; the PPs have {}", program.local_memory_bits_used,
                         local_memory_bits));
    }
    if (static_cast<int>(context.expressions.size()) < program.expressions) {
        fail(fmt::format("evaluates {} QEE expressions; the slot gives {}", program.expressions,
                         context.expressions.size()));
    }
    const int field_count = static_cast<int>(program.fields.size());
    for (const PpField& f : program.fields) {
        if (f.storage < 0 || f.storage >= program.storage_slots) {
            fail(fmt::format("field id {}: storage slot {} of {}", f.id, f.storage, program.storage_slots));
        }
    }
    for (std::size_t k = 0; k < program.instructions.size(); ++k) {
        const PpInstruction& in = program.instructions[k];
        const Operands uses = operands_of(in.op);
        const auto check_field = [&](bool used, int id, const char* role) {
            if (used && (id < 0 || id >= field_count)) {
                fail(fmt::format("instruction {} ({}): {} field id {} of {}", k, to_string(in.op), role, id,
                                 field_count));
            }
        };
        check_field(uses.dst, in.dst, "destination");
        check_field(uses.a, in.a, "operand a");
        check_field(uses.b, in.b, "operand b");
        const int max_shift = in.op == PpOp::Div ? 62 : 63;
        if (in.shift < 0 || in.shift > max_shift) {
            fail(fmt::format("instruction {} ({}): shift {} (0 to {} allowed)", k, to_string(in.op), in.shift,
                             max_shift));
        }
        if (in.op == PpOp::Lookup) {
            if (in.table < 0 || in.table >= static_cast<int>(program.tables.size())) {
                fail(fmt::format("instruction {}: table {} of {}", k, in.table, program.tables.size()));
            }
            const std::size_t entries = program.tables[static_cast<std::size_t>(in.table)].entries.size();
            if (entries == 0 || (entries & (entries - 1)) != 0) {
                fail(fmt::format("instruction {}: table {} has {} entries, not a power of two", k, in.table, entries));
            }
        }
        if (in.op == PpOp::Qee &&
            (in.expression < 0 || in.expression >= static_cast<int>(context.expressions.size()))) {
            fail(fmt::format("instruction {}: QEE expression {} of {}", k, in.expression, context.expressions.size()));
        }
        if (in.op == PpOp::Load || in.op == PpOp::Store) {
            const int bits = program.fields[static_cast<std::size_t>(in.op == PpOp::Load ? in.dst : in.a)].bits;
            const std::int64_t offset = std::int64_t{context.record_base_bit} + in.record_offset;
            if (offset < 0 || offset + bits > backing_store_bits) {
                fail(fmt::format(
                    "{} of {} bits at backing-store bit {} (record {} + {}) is past the {}-bit backing store",
                    to_string(in.op), bits, offset, context.record_base_bit, in.record_offset, backing_store_bits));
            }
        }
    }
}

}  // namespace pp5
