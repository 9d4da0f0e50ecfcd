// Levoy's volume-of-interest tool as PP programs: the region's scaling of opacity and the capping of
// the structures it cuts (geometry_programs.h declares them).
#include "kernels/levoy/geometry_programs.h"

#include "kernels/levoy/qee_geometry.h"
#include "sim/core/input_error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pp5 {

using namespace qee_geometry;

namespace {
constexpr int kDistanceShift = 8;    // distances in 1/256 voxel
constexpr int kQuadraticShift = 32;  // the ellipsoid's quadratic, before the QEE's shift back to 2^16

// The farthest any voxel lies from the region's centre, with two voxels to spare: what bounds the
// fields holding a voxel's region coordinates.
double region_reach(const RegionOfInterest& region, glm::ivec3 dims) {
    double reach = 0.0;
    for (int c = 0; c < 8; ++c)
        reach =
            std::max(reach, glm::length(box_corner(c, volume_lower(), volume_upper(dims)) - glm::dvec3(region.center)));
    return reach + 2.0;
}
}  // namespace

namespace {

std::int64_t whole(double x) { return static_cast<std::int64_t>(std::ceil(x)); }

// A box's distance outside its faces (negative inside), in 1/256 voxel: the largest face distance.
PpField emit_box_distance(PpProgramBuilder& b, const RegionOfInterest& region, double reach) {
    PpField distance;
    for (int i = 0; i < 3; ++i) {
        const PpField q = b.qee("region coordinate", i, pp_bits_for_range(-whole(reach * 256), whole(reach * 256)),
                                true, kQeeShift - kDistanceShift);
        const PpField aq = b.abs_diff_const("|region coordinate|", q, 0);
        b.release(q);
        const PpField out = b.add_const("face distance", aq, -std::llround(region.half_size[i] * 256.0));
        b.release(aq);
        if (!distance.valid()) {
            distance = out;
            continue;
        }
        // distance = max(distance, out): copy first (a copy under a partial mask would leave the
        // disabled PPs' copies unset), then overwrite where the new face is farther.
        const PpField widened = b.move("distance", distance);
        const PpField larger = b.sub("face distance - distance", out, distance);
        b.release(distance);
        b.enable_if(larger, PpCompare::Greater, 0);
        b.release(larger);
        b.assign(widened, out);
        b.enable_all();
        b.release(out);
        distance = widened;
    }
    return distance;
}

// An ellipsoid's distance outside its surface, in 1/256 voxel, measured along its smallest radius:
// (sqrt(s) - 1) r_min for its quadratic s (1 on the surface).
PpField emit_ellipsoid_distance(PpProgramBuilder& b, const RegionOfInterest& region, double reach) {
    const double r_min = std::min({region.half_size.x, region.half_size.y, region.half_size.z});
    const double s_max = reach * reach / (r_min * r_min);
    if (s_max * 65536.0 >= std::ldexp(1.0, kMaxPpFieldBits - 2)) {
        throw InputError("scenario", "region.half_size",
                         "an ellipsoid this thin (smallest radius " + std::to_string(r_min) +
                             " voxels) this far from the volume's voxels is past the PPs' 48-bit fixed point; use "
                             "a box or thicken it");
    }
    const PpField s = b.qee("ellipsoid quadratic", 0, pp_bits_for_range(-whole(s_max * 65536), whole(s_max * 65536)),
                            true, kQuadraticShift - 16);
    const PpField positive = b.max_const("ellipsoid quadratic", s, 0);
    b.release(s);
    const PpField root = b.sqrt("ellipsoid radius", positive);  // sqrt(s) x 256
    b.release(positive);
    const PpField offset = b.add_const("ellipsoid radius - 1", root, -256);
    b.release(root);
    const PpField distance = b.mul_const("distance", offset, std::llround(r_min * 256.0), 8);
    b.release(offset);
    return distance;
}

// w: 0 inside, 256 outside, linear across the transition.
PpField emit_transition_weight(PpProgramBuilder& b, const RegionOfInterest& region, const PpField& distance) {
    if (region.transition > 0.0f) {
        const PpField u = b.add_const("distance + transition / 2", distance, std::llround(region.transition * 128.0));
        const PpField ramp = b.mul_const("transition ramp", u, std::llround(65536.0 / region.transition), 16);
        b.release(u);
        const PpField low = b.max_const("transition ramp", ramp, 0);
        b.release(ramp);
        const PpField w = b.min_const("transition weight", low, 256);
        b.release(low);
        return w;
    }
    const PpField w = b.set_const("transition weight", 0, 9, false);
    b.enable_if(distance, PpCompare::Greater, 0);
    b.assign_const(w, 256);
    b.enable_all();
    return w;
}

}  // namespace

PpProgram build_region_program(const RegionOfInterest& region, glm::ivec3 dims, const PpProgramInputs& inputs) {
    const VoxelRecordLayout& layout = inputs.layout;
    const std::int64_t opacity_max = (std::int64_t{1} << layout.opacity_bits) - 1;
    const double reach = region_reach(region, dims);
    PpProgramBuilder b("region of interest", inputs.local_memory_bits);
    const PpField distance = region.shape == RegionOfInterest::Shape::Box ? emit_box_distance(b, region, reach)
                                                                          : emit_ellipsoid_distance(b, region, reach);
    const PpField w = emit_transition_weight(b, region, distance);
    b.release(distance);
    // The opacity times the factor w moves from scale_inside to scale_outside, clamped to its codes.
    const PpField change =
        b.mul_const("factor change", w, std::llround((region.scale_outside - region.scale_inside) * 256.0), 8);
    b.release(w);
    const PpField factor = b.add_const("opacity factor", change, std::llround(region.scale_inside * 256.0));
    b.release(change);
    const PpField a = b.load("opacity", layout.opacity_offset(), layout.opacity_bits, false);
    const PpField scaled = b.mul("scaled opacity", a, factor, 8);
    b.release(a);
    b.release(factor);
    const PpField low = b.max_const("scaled opacity", scaled, 0);
    b.release(scaled);
    const PpField clamped = b.min_const("scaled opacity", low, opacity_max);
    b.release(low);
    b.store(clamped, layout.opacity_offset(), layout.opacity_bits);
    b.release(clamped);
    return b.finish();
}

namespace {

constexpr int kAxisShift = 12;  // the box's face normals' components, in 1/4096

// Where a voxel lies against the box's pairs of faces: on which side of the centre along each axis,
// and whether it is in that pair's band (the transition around a face it is nearest, not beyond the
// band outside).
struct CapSides {
    std::array<PpField, 3> below, in_band;
};

// The box's face distances and sides, as the region program finds them; then which faces' bands hold
// the voxel.
CapSides emit_cap_sides(PpProgramBuilder& b, const RegionOfInterest& region, int first_expression,
                        std::int64_t coordinate_limit, std::int64_t half_band) {
    CapSides sides;
    std::array<PpField, 3> face;
    for (int i = 0; i < 3; ++i) {
        const PpField q =
            b.qee("cap: region coordinate", first_expression + i,
                  pp_bits_for_range(-coordinate_limit, coordinate_limit), true, kQeeShift - kDistanceShift);
        sides.below[i] = b.set_const("cap: below the centre", 0, 1, false);
        b.enable_if(q, PpCompare::Less, 0);
        b.assign_const(sides.below[i], 1);
        b.enable_all();
        const PpField aq = b.abs_diff_const("cap: |region coordinate|", q, 0);
        b.release(q);
        face[i] = b.add_const("cap: face distance", aq, -std::llround(region.half_size[i] * 256.0));
        b.release(aq);
    }
    const PpField distance = b.move("cap: distance", face[0]);
    for (int i = 1; i < 3; ++i) {
        const PpField larger = b.sub("cap: face distance - distance", face[i], distance);
        b.enable_if(larger, PpCompare::Greater, 0);
        b.release(larger);
        b.assign(distance, face[i]);
        b.enable_all();
    }
    for (int i = 0; i < 3; ++i) {
        sides.in_band[i] = b.set_const("cap: in the face's band", 0, 1, false);
        b.enable_if(face[i], PpCompare::Greater, -half_band);
        b.assign_const(sides.in_band[i], 1);
        b.enable_all();
        b.release(face[i]);
    }
    b.enable_if(distance, PpCompare::GreaterEqual, half_band);  // beyond the band outside: no cap
    for (int i = 0; i < 3; ++i) b.assign_const(sides.in_band[i], 0);
    b.enable_all();
    b.release(distance);
    return sides;
}

// Caps the gradient along the box's axis i where the voxel is in that pair's band: half of the
// change that makes the gradient's component along the outward normal n = s a (s = -1 below the
// centre) equal to the value's rise above air, f - f_air.
void emit_cap_axis(PpProgramBuilder& b, glm::vec3 axis, const PpField& rise, CapSides& sides, int i,
                   std::array<PpField, 3>& gradient) {
    const auto component = [&](int k) { return std::llround(static_cast<double>(axis[k]) * (1 << kAxisShift)); };
    PpField along;  // g.a for this face pair's axis a
    for (int k = 0; k < 3; ++k) {
        if (component(k) == 0) continue;
        along = b.accumulate("cap: gradient along the axis", along,
                             b.mul_const("cap: gradient along the axis", gradient[static_cast<std::size_t>(k)],
                                         component(k), kAxisShift));
    }
    // Twice the change of g is s (f - f_air) - g.a.
    const PpField change = b.sub("cap: change", rise, along);
    const PpField other_side = b.add("cap: change", rise, along);
    b.release(along);
    const PpField negated = b.mul_const("cap: change", other_side, -1);
    b.release(other_side);
    b.enable_if(sides.below[i], PpCompare::Equal, 1);
    b.assign(change, negated);
    b.enable_all();
    b.release(negated);
    b.release(sides.below[i]);
    b.enable_if(sides.in_band[i], PpCompare::Equal, 0);
    b.assign_const(change, 0);
    b.enable_all();
    b.release(sides.in_band[i]);
    const PpField half = b.mul_const("cap: change / 2", change, 1, 1);
    b.release(change);
    for (int k = 0; k < 3; ++k) {
        if (component(k) == 0) continue;
        const PpField term = b.mul_const("cap: change along the axis", half, component(k), kAxisShift);
        PpField& g = gradient[static_cast<std::size_t>(k)];
        const PpField capped = b.add("cap: gradient", g, term);
        b.release(term);
        b.release(g);
        g = capped;
    }
    b.release(half);
}

}  // namespace

GradientRewrite region_cap(const RegionOfInterest& region, glm::ivec3 dims, const PpProgramInputs& inputs,
                           int first_expression) {
    if (region.shape != RegionOfInterest::Shape::Box || !(region.transition > 0.0f))
        throw std::logic_error("region_cap: capping needs a box with a transition (validate_region refuses the rest)");
    const auto coordinate_limit = static_cast<std::int64_t>(std::ceil(region_reach(region, dims) * 256.0));
    return [region, inputs, first_expression, coordinate_limit](PpProgramBuilder& b, const PpField& value,
                                                                std::array<PpField, 3>& gradient) {
        const std::int64_t half_band = std::llround(region.transition * 128.0);  // T / 2 in 1/256 voxel
        CapSides sides = emit_cap_sides(b, region, first_expression, coordinate_limit, half_band);
        // f - f_air in gradient codes (value units per voxel times gradient_scale).
        const double codes_per_value =
            static_cast<double>(inputs.quantization.gradient_scale / inputs.quantization.value_scale);
        const PpField rise = b.mul_const("cap: value above air", value, std::llround(codes_per_value * 256.0), 8);
        for (int i = 0; i < 3; ++i) emit_cap_axis(b, region.axis(i), rise, sides, i, gradient);
        b.release(rise);
    };
}

std::vector<QeeCoefficients> region_expressions(const RegionOfInterest& region, const SlotFrame& frame) {
    const glm::dvec3 origin(frame.origin);
    const glm::dvec3 center(region.center);
    std::vector<QeeCoefficients> out;
    if (region.shape == RegionOfInterest::Shape::Box) {
        for (int i = 0; i < 3; ++i) {
            const glm::dvec3 a(region.axis(i));
            out.push_back(linear(a, -glm::dot(a, center), origin, kScale));
        }
        return out;
    }
    // sum_i ((k_i + u_i x + v_i y) / r_i)^2 with q_i = a_i . (origin - c) + a_i.x x + a_i.y y.
    QeeCoefficients q;
    double A = 0, B = 0, C = 0, D = 0, E = 0, F = 0;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 a(region.axis(i));
        const double k = glm::dot(a, origin - center);
        const double u = a.x;
        const double v = a.y;
        const double w = 1.0 / (static_cast<double>(region.half_size[i]) * static_cast<double>(region.half_size[i]));
        A += u * u * w;
        B += 2.0 * u * v * w;
        C += v * v * w;
        D += 2.0 * k * u * w;
        E += 2.0 * k * v * w;
        F += k * k * w;
    }
    const double scale = std::ldexp(1.0, kQuadraticShift);
    q.a = std::llround(A * scale);
    q.b = std::llround(B * scale);
    q.c = std::llround(C * scale);
    q.d = std::llround(D * scale);
    q.e = std::llround(E * scale);
    q.f = std::llround(F * scale);
    out.push_back(q);
    return out;
}

}  // namespace pp5
