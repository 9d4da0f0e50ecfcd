#pragma once
// What each voxel slot of a PP's backing store holds, and how the volume's values and gradients
// become the integers stored there. Levoy's budget is 8 bytes a voxel: an 8-bit value, a gradient of
// three 8-bit components, then the results, 8-bit red, green, blue and opacity. The widths are
// parameters, so "fewer bytes per voxel" is an experiment, not an edit.
//
// Quantisation: the value code is v = round((f - offset) * value_scale), where value_scale is 1 when
// an integer volume's range fits the code (so an 8-bit scan is stored exactly) and otherwise maps the
// range onto every code. Gradient components (central differences, value units per voxel) are stored
// as round(g * gradient_scale), signed, with gradient_scale chosen so the largest component of the
// volume just fits. Colours and opacity are codes of 1/(2^bits - 1).

#include "scene/reference/gradient_field.h"
#include "scene/volume/volume.h"

#include <cstdint>

namespace pp5 {

struct VoxelRecordLayout {
    int value_bits = 8;
    int gradient_bits = 8;  // per component, signed
    int color_bits = 8;     // per channel
    int opacity_bits = 8;
    // The precomputed light of the stationary lights (Levoy 1989), in 1/256ths, unsigned; 0 when the
    // record keeps none. It is a result like the colours, kept only while the stationary lights stay.
    int stationary_light_bits = 0;

    // Bit offsets within the record, in this order.
    int value_offset() const { return 0; }
    int gradient_offset(int axis) const { return value_bits + axis * gradient_bits; }
    int color_offset(int channel) const { return value_bits + 3 * gradient_bits + channel * color_bits; }
    int opacity_offset() const { return value_bits + 3 * gradient_bits + 3 * color_bits; }
    int stationary_light_offset() const { return opacity_offset() + opacity_bits; }
    int bits() const { return stationary_light_offset() + stationary_light_bits; }
};

struct VoxelQuantization {
    float value_offset = 0.0f;
    float value_scale = 1.0f;     // codes per value unit
    float gradient_scale = 1.0f;  // codes per (value unit per voxel)
    int value_max_code = 255;
    int gradient_max_code = 127;

    // The quantisation of `volume` and its gradients (central differences) for `layout`.
    static VoxelQuantization choose(const Volume& volume, const VoxelRecordLayout& layout);
    // The same rule from the ranges alone: values from value_min to value_max (stored exactly when
    // they are integers that fit the code), gradient components up to largest_gradient in magnitude.
    static VoxelQuantization for_ranges(float value_min, float value_max, bool integer_values, float largest_gradient,
                                        const VoxelRecordLayout& layout);

    std::int64_t value_code(float f) const;
    std::int64_t gradient_code(float g) const;
    float value_of_code(double code) const { return static_cast<float>(code / value_scale + value_offset); }
};

}  // namespace pp5
