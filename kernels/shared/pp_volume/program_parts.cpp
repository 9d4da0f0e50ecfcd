#include "kernels/shared/pp_volume/program_parts.h"

namespace pp5::program_parts {

VoxelInputs load_inputs(PpProgramBuilder& b, const VoxelRecordLayout& layout) {
    VoxelInputs in;
    in.value = b.load("value", layout.value_offset(), layout.value_bits, false);
    static const char* names[3] = {"gx", "gy", "gz"};
    for (int axis = 0; axis < 3; ++axis)
        in.gradient[axis] = b.load(names[axis], layout.gradient_offset(axis), layout.gradient_bits, true);
    return in;
}

PpField magnitude_times_four(PpProgramBuilder& b, const std::array<PpField, 3>& v) {
    PpField sum = b.mul("g2x", v[0], v[0]);
    for (int axis = 1; axis < 3; ++axis) {
        const PpField square = b.mul("g2", v[axis], v[axis]);
        const PpField next = b.add("g2sum", sum, square);
        b.release(square);
        b.release(sum);
        sum = next;
    }
    const PpField scaled = b.mul_const("g2x16", sum, 16);
    b.release(sum);
    const PpField magnitude = b.sqrt("gmag4", scaled);
    b.release(scaled);
    return magnitude;
}

PpField rounded_shift(PpProgramBuilder& b, const std::string& name, PpField x, int shift) {
    const PpField biased = b.add_const(name + "_biased", x, std::int64_t{1} << (shift - 1));
    b.release(x);
    const PpField result = b.move(name, biased, shift);
    b.release(biased);
    return result;
}

PpField to_code(PpProgramBuilder& b, const std::string& name, PpField fraction256, std::int64_t max_code) {
    const PpField scaled = b.mul_const(name + "_scaled", fraction256, max_code);
    const PpField code = rounded_shift(b, name, scaled, kOneShift);
    const PpField clamped = b.min_const(name + "_clamped", code, max_code);
    b.release(code);
    return clamped;
}

}  // namespace pp5::program_parts
