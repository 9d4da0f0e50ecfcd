#include "kernels/shared/pp_volume/shading_programs.h"

#include "kernels/shared/pp_volume/program_parts.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pp5 {

namespace {

using namespace program_parts;  // the fixed-point pieces both programs are built from

// min(1, (numerator << shift) / denominator) in 1/256ths where the numerator is positive, and 0
// where it is not: a voxel with no gradient (zero over zero) has no normal and gets no direct light.
PpField positive_ratio(PpProgramBuilder& b, const std::string& name, PpField numerator, PpField denominator,
                       int shift) {
    const PpField ratio = b.set_const(name + "_ratio", 0, kOneShift + 2, false);
    b.enable_if(numerator, PpCompare::Greater, 0);
    const PpField quotient = b.div(name + "_quotient", numerator, denominator, shift, kOneShift + 2);
    b.assign(ratio, quotient);
    b.release(quotient);
    b.enable_all();
    const PpField clamped = b.min_const(name, ratio, kOne);
    b.release(ratio);
    return clamped;
}

// 256 (N . d) for the unit normal N = -w/|w| and a unit direction d, where w is the gradient: the
// dot product -w.d in 1/256ths, divided by |w| = gmag4 / 4. Only where the result is positive.
PpField normal_dot(PpProgramBuilder& b, const std::string& name, const std::array<PpField, 3>& w, PpField gmag4,
                   glm::vec3 direction) {
    PpField dot;
    for (int axis = 0; axis < 3; ++axis) {
        const std::int64_t k = fixed(-direction[axis], kOneShift);
        if (k == 0) continue;
        dot = b.accumulate(name + "_sum", dot, b.mul_const(name + "_term", w[axis], k));
    }
    if (!dot.valid()) return b.set_const(name, 0, kOneShift + 1, false);
    const PpField positive = b.max_const(name + "_positive", dot, 0);
    b.release(dot);
    // 256 (-w.d)/|w| = 4 (256 (-w.d)) / gmag4.
    const PpField clamped = positive_ratio(b, name, positive, gmag4, 2);
    b.release(positive);
    return clamped;
}

// 256 (N . V) with V the unit direction from each voxel to the eye (a perspective headlight, where
// L = V): the QEE gives each PP its voxel's vector e to the eye, so N . V = -w.e / (|w| |e|), taken
// only where positive.
PpField normal_dot_eye(PpProgramBuilder& b, const std::array<PpField, 3>& w, PpField gmag4) {
    std::array<PpField, 3> eye;
    for (int axis = 0; axis < 3; ++axis) eye[axis] = b.qee("to_eye", kToEyeExpression + axis, 12, true, kQeeShift);
    const PpField eye4 = magnitude_times_four(b, eye);
    PpField dot;
    for (int axis = 0; axis < 3; ++axis) {
        const PpField term = b.mul("n_dot_v_term", w[axis], eye[axis]);
        b.release(eye[axis]);
        dot = b.accumulate("n_dot_v_sum", dot, term);
    }
    // -w.e, clamped at zero: the faces turned to the eye.
    const PpField facing = b.mul_const("n_dot_v_facing", dot, -1);
    b.release(dot);
    const PpField positive = b.max_const("n_dot_v_positive", facing, 0);
    b.release(facing);
    // 256 (-w.e) / (|w| |e|) = 4096 (-w.e) / (gmag4 eye4).
    const PpField lengths = b.mul("n_dot_v_lengths", gmag4, eye4);
    b.release(eye4);
    const PpField clamped = positive_ratio(b, "n_dot_l", positive, lengths, 12);
    b.release(positive);
    b.release(lengths);
    return clamped;
}

// x^n for x in 1/256ths: by repeated squaring for whole n (each product rounded down to 1/256ths),
// by a broadcast table otherwise.
PpField power_256(PpProgramBuilder& b, PpField x, float n) {
    if (n >= 0.0f && n <= 1024.0f && n == std::floor(n)) {
        auto e = static_cast<int>(n);
        PpField result = b.set_const("spec", kOne, kOneShift + 1, false);
        PpField base = b.move("spec_base", x);
        while (e > 0) {
            if (e & 1) {
                const PpField next = b.mul("spec", result, base, kOneShift);
                b.release(result);
                result = next;
            }
            e >>= 1;
            if (e > 0) {
                const PpField squared = b.mul("spec_base", base, base, kOneShift);
                b.release(base);
                base = squared;
            }
        }
        b.release(base);
        return result;
    }
    PpTable table{"specular_power", std::vector<std::int64_t>(std::size_t{1} << x.bits)};
    for (std::size_t i = 0; i < table.entries.size(); ++i) {
        const double t = std::min(1.0, static_cast<double>(i) / static_cast<double>(kOne));
        table.entries[i] = fixed(std::pow(t, static_cast<double>(n)), kOneShift);
    }
    return b.lookup("spec", x, std::move(table), kOneShift + 1, false);
}

// The gradient in world units (each component scaled by the smallest spacing over its own, 6
// fraction bits, when the volume is anisotropic) and 4 |w|: what every normal is made from. The
// gradient fields are released when scaled copies replace them.
struct NormalInputs {
    std::array<PpField, 3> w;
    PpField gmag4;
};

NormalInputs normal_inputs(PpProgramBuilder& b, const std::array<PpField, 3>& gradient, glm::vec3 spacing) {
    NormalInputs n{gradient, {}};
    const float finest = std::min({spacing.x, spacing.y, spacing.z});
    if (spacing != glm::vec3(finest)) {
        for (int axis = 0; axis < 3; ++axis) {
            n.w[axis] = b.mul_const("world_gradient", gradient[axis], fixed(finest / spacing[axis], 6));
            b.release(gradient[axis]);
        }
    }
    n.gmag4 = magnitude_times_four(b, n.w);
    return n;
}

void release(PpProgramBuilder& b, const NormalInputs& n) {
    for (const PpField& f : n.w) b.release(f);
    b.release(n.gmag4);
}

// s [k_d (N.L) + k_s (N.H)^n] in 1/256ths for a light in a fixed direction, zero where it does not
// reach the face (N.L <= 0). Every PP is enabled on return.
PpField fixed_light_lit(PpProgramBuilder& b, const std::string& name, const NormalInputs& n,
                        const PhongLighting& lighting, glm::vec3 to_light, glm::vec3 to_viewer, float intensity) {
    const PpField n_dot_l = normal_dot(b, name + "_n_dot_l", n.w, n.gmag4, to_light);
    PpField n_dot_h;
    const glm::vec3 halfway = to_light + to_viewer;
    if (lighting.specular > 0.0f && glm::length(halfway) > 0.0f)
        n_dot_h = normal_dot(b, name + "_n_dot_h", n.w, n.gmag4, glm::normalize(halfway));
    b.enable_if(n_dot_l, PpCompare::Greater, 0);
    PpField lit = b.mul_const(name + "_diffuse", n_dot_l, fixed(intensity * lighting.diffuse, kOneShift));
    if (n_dot_h.valid()) {
        const PpField spec = power_256(b, n_dot_h, lighting.shininess);
        b.release(n_dot_h);
        const PpField specular = b.mul_const(name + "_specular", spec, fixed(intensity * lighting.specular, kOneShift));
        b.release(spec);
        const PpField sum = b.add(name + "_sum", lit, specular);
        b.release(specular);
        b.release(lit);
        lit = sum;
    }
    lit = rounded_shift(b, name, lit, kOneShift);
    b.enable_all();
    const PpField out = b.set_const(name, 0, lit.bits, false);
    b.enable_if(n_dot_l, PpCompare::Greater, 0);
    b.assign(out, lit);
    b.enable_all();
    b.release(lit);
    b.release(n_dot_l);
    return out;
}

// The stationary lights' sum, in 1/256ths. Highlights use the view's central direction, as the key
// light's do under a fixed light.
PpField stationary_lit(PpProgramBuilder& b, const NormalInputs& n, const PhongLighting& lighting, glm::vec3 to_viewer) {
    PpField sum;
    for (const StationaryLight& light : lighting.stationary_lights)
        sum = b.accumulate(
            "stationary_sum", sum,
            fixed_light_lit(b, "stationary", n, lighting, glm::normalize(light.direction), to_viewer, light.intensity));
    return sum;
}

// lit / (k1 + k2 d), with d from the QEE (256 d, clamped to [0, 256]); releases `lit`.
PpField depth_cued(PpProgramBuilder& b, PpField lit, const PhongLighting& lighting) {
    const PpField raw = b.qee("depth_raw", kDepthExpression, kOneShift + 3, true, kQeeShift);
    const PpField low = b.max_const("depth_low", raw, 0);
    b.release(raw);
    const PpField depth = b.min_const("depth", low, kOne);
    b.release(low);
    const PpField cue = b.mul_const("cue", depth, fixed(lighting.depth_cue_k2, kOneShift), kOneShift);
    b.release(depth);
    const PpField divisor = b.add_const("cue_divisor", cue, fixed(lighting.depth_cue_k1, kOneShift));
    b.release(cue);
    const PpField one = b.set_const("one", 1, 1, false);
    const float smallest_divisor = std::min(lighting.depth_cue_k1, lighting.depth_cue_k1 + lighting.depth_cue_k2);
    const int attenuation_bits = pp_bits_for_range(0, fixed(1.0 / smallest_divisor, kOneShift) + 1);
    const PpField attenuation = b.div("attenuation", one, divisor, 2 * kOneShift, attenuation_bits);
    b.release(one);
    b.release(divisor);
    const PpField cued = b.mul("lit_cued", lit, attenuation, kOneShift);
    b.release(attenuation);
    b.release(lit);
    return cued;
}

// Base colour c_p from the colour map: one broadcast table per channel, in colour codes.
std::array<PpField, 3> emit_base_colours(PpProgramBuilder& b, const PpField& value, const ColorMap& color_map,
                                         const VoxelRecordLayout& layout, const VoxelQuantization& q) {
    const std::int64_t color_max = (std::int64_t{1} << layout.color_bits) - 1;
    std::array<PpField, 3> base;
    static const char* channel_names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
        PpTable table = value_table(std::string("base_") + channel_names[c], value, q, [&](float f) {
            return fixed(color_map.color(f)[c] * static_cast<float>(color_max), 0);
        });
        base[c] = b.lookup(std::string("base_") + channel_names[c], value, std::move(table), layout.color_bits, false);
    }
    return base;
}

// The key light's k_d (N.L) + k_s (N.H)^n, in 1/256ths, where it reaches the face (0 elsewhere), the
// highlight from N.L itself under a headlight; depth-cued when `cue`. Releases n_dot_l and n_dot_h.
PpField emit_key_light(PpProgramBuilder& b, const PpField& n_dot_l, const PpField& n_dot_h,
                       const PhongLighting& lighting, bool cue) {
    b.enable_if(n_dot_l, PpCompare::Greater, 0);
    PpField lit = b.mul_const("diffuse", n_dot_l, fixed(lighting.diffuse, kOneShift));
    const PpField highlight_source = lighting.light_follows_camera ? n_dot_l : n_dot_h;
    if (highlight_source.valid() && lighting.specular > 0.0f) {
        const PpField spec = power_256(b, highlight_source, lighting.shininess);
        const PpField specular = b.mul_const("specular", spec, fixed(lighting.specular, kOneShift));
        b.release(spec);
        const PpField sum = b.add("lit_sum", lit, specular);
        b.release(specular);
        b.release(lit);
        lit = sum;
    }
    if (n_dot_h.valid()) b.release(n_dot_h);
    lit = rounded_shift(b, "lit", lit, kOneShift);
    if (cue) lit = depth_cued(b, lit, lighting);
    b.enable_all();
    const PpField light = b.set_const("light", 0, lit.bits, false);
    b.enable_if(n_dot_l, PpCompare::Greater, 0);
    b.assign(light, lit);
    b.enable_all();
    b.release(lit);
    b.release(n_dot_l);
    return light;
}

// c = c_p (k_a + light), rounded and clamped to the colour code, stored; releases base and light.
void emit_shaded_colours(PpProgramBuilder& b, std::array<PpField, 3>& base, const PpField& light,
                         const PhongLighting& lighting, const VoxelRecordLayout& layout) {
    const std::int64_t color_max = (std::int64_t{1} << layout.color_bits) - 1;
    const PpField factor = b.add_const("factor", light, fixed(lighting.ambient, kOneShift));
    b.release(light);
    for (int c = 0; c < 3; ++c) {
        const PpField product = b.mul("shaded", base[c], factor);
        b.release(base[c]);
        const PpField code = rounded_shift(b, "color", product, kOneShift);
        const PpField clamped = b.min_const("color_clamped", code, color_max);
        b.release(code);
        b.store(clamped, layout.color_offset(c), layout.color_bits);
        b.release(clamped);
    }
    b.release(factor);
}

}  // namespace

PpProgram build_shading_program(const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view,
                                const PpProgramInputs& inputs, const GradientRewrite& rewrite) {
    const VoxelRecordLayout& layout = inputs.layout;
    PpProgramBuilder b("shade", inputs.local_memory_bits);
    VoxelInputs in = load_inputs(b, layout);
    std::array<PpField, 3> base = emit_base_colours(b, in.value, color_map, layout, inputs.quantization);
    if (rewrite) rewrite(b, in.value, in.gradient);
    b.release(in.value);
    const NormalInputs normals = normal_inputs(b, in.gradient, inputs.spacing);

    const glm::vec3 to_viewer = -view.forward;
    const glm::vec3 to_light = lighting.light_follows_camera ? to_viewer : glm::normalize(lighting.light_direction);
    const bool eye_per_voxel = lighting.light_follows_camera && view.projection == Projection::Perspective;
    const PpField n_dot_l = eye_per_voxel ? normal_dot_eye(b, normals.w, normals.gmag4)
                                          : normal_dot(b, "n_dot_l", normals.w, normals.gmag4, to_light);
    PpField n_dot_h;
    const glm::vec3 halfway = to_light + to_viewer;
    if (!lighting.light_follows_camera && glm::length(halfway) > 0.0f)
        n_dot_h = normal_dot(b, "n_dot_h", normals.w, normals.gmag4, glm::normalize(halfway));
    // The stationary lights: from the record when a stationary-light pass has stored their sum there,
    // else computed here with the key light.
    const bool stationary = !lighting.stationary_lights.empty();
    const bool stored = stationary && layout.stationary_light_bits > 0;
    PpField stationary_light;
    if (stationary && !stored) stationary_light = stationary_lit(b, normals, lighting, to_viewer);
    release(b, normals);

    // With one light the depth cue divides only where it reaches; with several, the sum below.
    const bool cue = lighting.depth_cue_k2 != 0.0f;
    PpField light = emit_key_light(b, n_dot_l, n_dot_h, lighting, cue && !stationary);
    if (stationary) {
        if (stored)
            stationary_light =
                b.load("stationary_light", layout.stationary_light_offset(), layout.stationary_light_bits, false);
        const PpField total = b.add("all_lights", light, stationary_light);
        b.release(light);
        b.release(stationary_light);
        light = cue ? depth_cued(b, total, lighting) : total;
    }
    emit_shaded_colours(b, base, light, lighting, layout);
    return b.finish();
}

PpProgram build_stationary_light_program(const PhongLighting& lighting, const ShadingView& view,
                                         const PpProgramInputs& inputs, const GradientRewrite& rewrite) {
    const VoxelRecordLayout& layout = inputs.layout;
    if (layout.stationary_light_bits <= 0 || lighting.stationary_lights.empty())
        throw std::logic_error(
            "build_stationary_light_program: needs stationary lights and a record field for their sum");
    PpProgramBuilder b("stationary_lights", inputs.local_memory_bits);
    VoxelInputs in = load_inputs(b, layout);
    if (rewrite) rewrite(b, in.value, in.gradient);
    b.release(in.value);
    const NormalInputs normals = normal_inputs(b, in.gradient, inputs.spacing);
    const PpField sum = stationary_lit(b, normals, lighting, -view.forward);
    release(b, normals);
    // A sum beyond the field saturates (documented with levoy.stationary_light_bits).
    const PpField clamped =
        b.min_const("stationary_clamped", sum, (std::int64_t{1} << layout.stationary_light_bits) - 1);
    b.release(sum);
    b.store(clamped, layout.stationary_light_offset(), layout.stationary_light_bits);
    b.release(clamped);
    return b.finish();
}

std::array<QeeCoefficients, 4> slot_expressions(const ShadingView& view, const SlotFrame& frame, glm::vec3 spacing) {
    std::array<QeeCoefficients, 4> e{};
    const glm::vec3 origin = glm::vec3(frame.origin) * spacing;
    // A voxel at PP (x, y) sits at origin + (x sx, y sy, 0).
    if (view.radius > 0.0f) {
        // 256 depth = 256 ((p - centre).forward + radius) / (2 radius).
        const double scale = 256.0 / (2.0 * static_cast<double>(view.radius));
        QeeCoefficients& depth = e[kDepthExpression];
        depth.d = fixed(static_cast<double>(spacing.x * view.forward.x) * scale, kQeeShift);
        depth.e = fixed(static_cast<double>(spacing.y * view.forward.y) * scale, kQeeShift);
        depth.f =
            fixed((static_cast<double>(glm::dot(origin - view.center, view.forward)) + view.radius) * scale, kQeeShift);
    }
    const double eye_distance = glm::length(view.eye - view.center);
    if (view.projection == Projection::Perspective && eye_distance > 0.0) {
        const double scale = 256.0 / eye_distance;
        for (int axis = 0; axis < 3; ++axis) {
            QeeCoefficients& to_eye = e[static_cast<std::size_t>(kToEyeExpression + axis)];
            to_eye.d = axis == 0 ? fixed(-static_cast<double>(spacing.x) * scale, kQeeShift) : 0;
            to_eye.e = axis == 1 ? fixed(-static_cast<double>(spacing.y) * scale, kQeeShift) : 0;
            to_eye.f = fixed(static_cast<double>(view.eye[axis] - origin[axis]) * scale, kQeeShift);
        }
    }
    return e;
}

}  // namespace pp5
