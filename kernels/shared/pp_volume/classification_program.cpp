#include "kernels/shared/pp_volume/program_parts.h"
#include "kernels/shared/pp_volume/shading_programs.h"

#include <algorithm>
#include <string>

namespace pp5 {

namespace {

using namespace program_parts;  // the fixed-point pieces both programs are built from

// Opacity of one isovalue contour (Levoy 1988, eq. 3) in 1/256ths. With D = 16 |v - v_f| (the value
// distance in 1/16 codes) and R = 16 (codes per value unit) r |g|, the opacity is
// alpha_v (1 - D / R) where D <= R, and 0 elsewhere; D = R = 0 (a flat region at the isovalue) gives
// alpha_v, as in the floating-point rule.
PpField isovalue_opacity(PpProgramBuilder& b, const IsovalueContour& contour, PpField value16, PpField gmag4,
                         const VoxelQuantization& q) {
    const std::int64_t target16 = fixed((contour.value - q.value_offset) * q.value_scale, 4);
    const PpField distance = b.abs_diff_const("iso_distance", value16, target16);
    // |g| = gmag4 / (4 gradient_scale), so 16 value_scale r |g| = gmag4 (4 r value_scale / gradient_scale).
    constexpr int kShift = 12;
    const PpField reach = b.mul_const(
        "iso_reach", gmag4, fixed(4.0 * contour.thickness * q.value_scale / q.gradient_scale, kShift), kShift);

    const PpField ratio = b.set_const("iso_ratio", 0, kOneShift + 1, false);
    b.enable_if(reach, PpCompare::Greater, 0);
    const PpField quotient = b.div("iso_quotient", distance, reach, kOneShift, kOneShift + 1);
    b.assign(ratio, quotient);
    b.release(quotient);
    b.enable_all();

    const PpField margin = b.sub("iso_margin", reach, distance);
    b.release(distance);
    b.release(reach);
    const PpField opacity = b.set_const("iso_opacity", 0, kOneShift + 1, false);
    b.enable_if(margin, PpCompare::GreaterEqual, 0);
    const PpField falloff = b.abs_diff_const("iso_falloff", ratio, kOne);  // 256 - ratio, as ratio <= 256 here
    const PpField scaled = b.mul_const("iso_scaled", falloff, fixed(contour.opacity, kOneShift), kOneShift);
    b.assign(opacity, scaled);
    b.release(scaled);
    b.release(falloff);
    b.enable_all();
    b.release(margin);
    b.release(ratio);
    return opacity;
}

// Opacity in 1/256ths from the classification.
PpField opacity_256(PpProgramBuilder& b, const Classification& c, const VoxelInputs& in, const VoxelQuantization& q) {
    switch (c.kind) {
        case ClassificationKind::PiecewiseLinear: {
            PpTable table =
                value_table("opacity", in.value, q, [&](float f) { return fixed(c.opacity(f, 0.0f), kOneShift); });
            return b.lookup("opacity256", in.value, std::move(table), kOneShift + 1, false);
        }
        case ClassificationKind::RegionBoundaries: {
            // alpha = |g| w(f), with w the interpolated point opacities: a table of w scaled by
            // 1 / (4 gradient_scale) times the magnitude the PPs compute.
            const PpField gmag4 = magnitude_times_four(b, in.gradient);
            PpTable table = value_table("boundary_weight", in.value, q, [&](float f) {
                return fixed(static_cast<double>(c.opacity(f, 1.0f)) / (4.0 * q.gradient_scale), 2 * kOneShift);
            });
            std::int64_t largest = 0;
            for (auto e : table.entries) largest = std::max(largest, e);
            const PpField weight = b.lookup("boundary_weight", in.value, std::move(table),
                                            std::max(1, pp_bits_for_range(0, largest)), false);
            const PpField product = b.mul("boundary_product", gmag4, weight, kOneShift);
            b.release(weight);
            b.release(gmag4);
            const PpField opacity = b.min_const("opacity256", product, kOne);
            b.release(product);
            return opacity;
        }
        case ClassificationKind::IsovalueContours:
        default: {
            if (c.contours.empty()) return b.set_const("opacity256", 0, kOneShift + 1, false);
            const PpField gmag4 = magnitude_times_four(b, in.gradient);
            const PpField value16 = b.mul_const("value16", in.value, 16);
            // Several contours combine as 1 - prod(1 - alpha_n).
            PpField transparency;
            for (const IsovalueContour& contour : c.contours) {
                const PpField alpha = isovalue_opacity(b, contour, value16, gmag4, q);
                if (c.contours.size() == 1) {
                    b.release(value16);
                    b.release(gmag4);
                    return alpha;
                }
                const PpField clear = b.abs_diff_const("iso_clear", alpha, kOne);
                b.release(alpha);
                if (!transparency.valid()) {
                    transparency = clear;
                } else {
                    const PpField next = b.mul("transparency", transparency, clear, kOneShift);
                    b.release(transparency);
                    b.release(clear);
                    transparency = next;
                }
            }
            b.release(value16);
            b.release(gmag4);
            const PpField opacity = b.abs_diff_const("opacity256", transparency, kOne);
            b.release(transparency);
            return opacity;
        }
    }
}

}  // namespace

PpProgram build_classification_program(const Classification& classification, const PpProgramInputs& inputs) {
    PpProgramBuilder b("classify", inputs.local_memory_bits);
    const VoxelInputs in = load_inputs(b, inputs.layout);
    const PpField opacity = opacity_256(b, classification, in, inputs.quantization);
    const std::int64_t max_code = (std::int64_t{1} << inputs.layout.opacity_bits) - 1;
    const PpField code = to_code(b, "opacity", opacity, max_code);
    b.release(opacity);
    b.store(code, inputs.layout.opacity_offset(), inputs.layout.opacity_bits);
    return b.finish();
}

}  // namespace pp5
