#pragma once
// Internal to kernels/shared/pp_volume: the fixed-point pieces the classification and shading
// programs are both built from.

#include "kernels/shared/pp_volume/voxel_record.h"
#include "sim/pixel_processors/pp_program.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <string>

namespace pp5::program_parts {

// Fixed-point fractions of one: 256 stands for 1.0 in opacities, dot products and light factors.
inline constexpr int kOneShift = 8;
inline constexpr std::int64_t kOne = std::int64_t{1} << kOneShift;

// x with `shift` fraction bits, rounded to nearest.
inline std::int64_t fixed(double x, int shift) {
    return static_cast<std::int64_t>(std::llround(x * static_cast<double>(std::int64_t{1} << shift)));
}

// The inputs every program starts from: the value and the three gradient codes of the slot's voxel.
struct VoxelInputs {
    PpField value;
    std::array<PpField, 3> gradient;
};
VoxelInputs load_inputs(PpProgramBuilder& b, const VoxelRecordLayout& layout);

// 4 |v| for a vector of three fields: the square root of the sum of squares, taken with two extra
// fraction bits so small gradients keep their precision.
PpField magnitude_times_four(PpProgramBuilder& b, const std::array<PpField, 3>& v);

// A table over every value code: entry(f) for the value each code stands for.
template <class Entry>
PpTable value_table(const std::string& name, const PpField& value, const VoxelQuantization& q, Entry&& entry) {
    PpTable table{name, {}};
    const std::size_t size = std::size_t{1} << value.bits;
    table.entries.resize(size);
    for (std::size_t code = 0; code < size; ++code)
        table.entries[code] = entry(q.value_of_code(static_cast<double>(code)));
    return table;
}

// (x + 1/2) >> shift: a fixed-point product rounded to nearest. Releases x.
PpField rounded_shift(PpProgramBuilder& b, const std::string& name, PpField x, int shift);
// Scale a 0..256 fraction to a code of 0..max_code, rounded.
PpField to_code(PpProgramBuilder& b, const std::string& name, PpField fraction256, std::int64_t max_code);

}  // namespace pp5::program_parts
