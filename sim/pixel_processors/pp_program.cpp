#include "sim/pixel_processors/pp_program.h"

#include <algorithm>
#include <string>

namespace pp5 {

std::string to_string(PpOp op) {
    switch (op) {
        case PpOp::SetConst: return "set";
        case PpOp::Move: return "move";
        case PpOp::Add: return "add";
        case PpOp::Sub: return "sub";
        case PpOp::AddConst: return "add-const";
        case PpOp::AbsDiffConst: return "abs-diff-const";
        case PpOp::MinConst: return "min-const";
        case PpOp::MaxConst: return "max-const";
        case PpOp::Mul: return "mul";
        case PpOp::MulConst: return "mul-const";
        case PpOp::Div: return "div";
        case PpOp::Sqrt: return "sqrt";
        case PpOp::Lookup: return "lookup";
        case PpOp::Qee: return "qee";
        case PpOp::EnableAll: return "enable-all";
        case PpOp::EnableIf: return "enable-if";
        case PpOp::Load: return "load";
        case PpOp::Store: return "store";
    }
    return "?";
}

int PpTable::runs() const {
    int runs = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) runs += (i == 0 || entries[i] != entries[i - 1]) ? 1 : 0;
    return runs;
}

PpBystander bystander_of(const PpProgram& program) {
    PpBystander bystander;
    bool enabled = true;  // every PP starts enabled
    bool tested = false;  // whether a test has looked at it since then, or since the last EnableAll
    for (const PpInstruction& in : program.instructions) {
        // An instruction is counted with the enable bit it finds, as PpArray counts it.
        if (enabled) ++bystander.enabled_operations;
        if (in.op == PpOp::EnableAll) {
            enabled = true;
            tested = false;
        } else if (in.op == PpOp::EnableIf) {
            if (!tested) enabled = false;
            tested = true;
        } else if (in.op == PpOp::Store && enabled) {
            bystander.stores = true;
        }
    }
    return bystander;
}

int pp_bits_for_range(std::int64_t lo, std::int64_t hi) {
    if (lo > hi) std::swap(lo, hi);
    int bits = 1;
    if (lo < 0) {
        // Two's complement: b bits hold [-2^(b-1), 2^(b-1) - 1].
        while (bits < 64 && (lo < -(std::int64_t{1} << (bits - 1)) || hi > (std::int64_t{1} << (bits - 1)) - 1)) ++bits;
    } else {
        while (bits < 63 && hi > (std::int64_t{1} << bits) - 1) ++bits;  // 63 bits hold any non-negative int64
    }
    return bits;
}

}  // namespace pp5
