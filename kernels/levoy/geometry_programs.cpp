#include "kernels/levoy/geometry_programs.h"

#include "kernels/levoy/qee_geometry.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "sim/core/input_error.h"

namespace pp5 {

using namespace qee_geometry;

namespace {

// The largest |f| over the volume's box (a linear function peaks at a corner), plus a voxel of margin.
double bound(glm::dvec3 g, double h, glm::ivec3 dims) {
    double most = 0.0;
    for (int c = 0; c < 8; ++c)
        most = std::max(most, std::abs(glm::dot(g, box_corner(c, volume_lower(), volume_upper(dims))) + h));
    return most + glm::length(g) + 1.0;
}

int signed_bits(double magnitude) {
    const auto m = static_cast<std::int64_t>(std::ceil(magnitude * kScale)) + 1;
    return pp_bits_for_range(-m, m);
}

}  // namespace

PolygonProgramShape polygon_program_shape(const PreparedPolygon& polygon, int samples, glm::ivec3 dims,
                                          const VoxelRecordLayout& layout) {
    PolygonProgramShape shape;
    shape.samples = samples;
    shape.distance_bits = signed_bits(bound(polygon.normal, polygon.plane_offset, dims));
    for (std::size_t i = 0; i < polygon.edge_normals.size(); ++i)
        shape.edge_bits.push_back(signed_bits(bound(polygon.edge_normals[i], polygon.edge_offsets[i], dims)));
    // A covered voxel's centre may lie up to a voxel outside the polygon, where its linear colour and
    // opacity run past [0, 1]: size the QEE's fields for the polygon's box grown by a voxel (the program
    // clamps them).
    const std::int64_t color_max = (std::int64_t{1} << layout.color_bits) - 1;
    const std::int64_t opacity_max = (std::int64_t{1} << layout.opacity_bits) - 1;
    const LinearFunction* channels[4] = {&polygon.red, &polygon.green, &polygon.blue, &polygon.opacity};
    for (std::size_t k = 0; k < 4; ++k) {
        double most = 1.0;
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 corner = box_corner(c, glm::dvec3(polygon.lower) - 1.0, glm::dvec3(polygon.upper) + 1.0);
            most = std::max(most, std::abs(static_cast<double>((*channels[k])(glm::vec3(corner)))));
        }
        const auto limit =
            static_cast<std::int64_t>(std::ceil(most * static_cast<double>(k < 3 ? color_max : opacity_max))) + 2;
        shape.code_bits[k] = pp_bits_for_range(-limit, limit);
    }
    return shape;
}

PpProgram build_polygon_program(const PreparedPolygon& polygon, int samples, glm::ivec3 dims,
                                const PpProgramInputs& inputs) {
    return build_polygon_program(polygon_program_shape(polygon, samples, dims, inputs.layout), inputs);
}

namespace {

// Coverage: how many of the translated sample points fall in the polygon's sheet.
PpField emit_coverage_count(PpProgramBuilder& b, const PolygonProgramShape& shape) {
    const int samples = shape.samples;
    const int edges = static_cast<int>(shape.edge_bits.size());
    const int per_sample = 1 + edges;
    const PpField count = b.set_const("coverage count", 0, pp_bits_for_range(0, samples), false);
    for (int j = 0; j < samples; ++j) {
        b.enable_all();
        const PpField d = b.qee("plane distance", j * per_sample, shape.distance_bits, true, 0);
        const PpField ad = b.abs_diff_const("|plane distance|", d, 0);
        b.release(d);
        b.enable_if(ad, PpCompare::LessEqual, kPolygonSheetHalfWidth);
        b.release(ad);
        for (int i = 0; i < edges; ++i) {
            const PpField e =
                b.qee("edge function", j * per_sample + 1 + i, shape.edge_bits[static_cast<std::size_t>(i)], true, 0);
            b.enable_if(e, PpCompare::GreaterEqual, 0);
            b.release(e);
        }
        const PpField more = b.add_const("coverage count + 1", count, 1);
        b.assign(count, more);
        b.release(more);
    }
    return count;
}

// The polygon's colour or opacity code at this voxel (channel 3 is opacity), clamped to [0, max_code].
PpField emit_polygon_code(PpProgramBuilder& b, const PolygonProgramShape& shape, const char* name, int channel,
                          std::int64_t max_code) {
    const int first_color_expression = shape.samples * (1 + static_cast<int>(shape.edge_bits.size()));
    const PpField raw = b.qee(name, first_color_expression + channel,
                              shape.code_bits[static_cast<std::size_t>(channel)], true, kQeeShift);
    const PpField low = b.max_const(name, raw, 0);
    b.release(raw);
    const PpField clamped = b.min_const(name, low, max_code);
    b.release(low);
    return clamped;
}

// The voxel seen through the polygon's coverage: a = a_p + a_v (1 - a_p), and each colour
// (c_p a_p + c_v a_v (1 - a_p)) / a, stored over the voxel's own.
void emit_matte(PpProgramBuilder& b, const PolygonProgramShape& shape, const VoxelRecordLayout& layout,
                const PpField& a_p) {
    const std::int64_t color_max = (std::int64_t{1} << layout.color_bits) - 1;
    const std::int64_t opacity_max = (std::int64_t{1} << layout.opacity_bits) - 1;
    const PpField a_v = b.load("voxel opacity", layout.opacity_offset(), layout.opacity_bits, false);
    const PpField rest = b.set_const("opacity max", opacity_max);
    const PpField clear = b.sub("1 - a_p", rest, a_p);
    const PpField behind = b.mul("a_v (1 - a_p)", a_v, clear);
    b.release(a_v);
    b.release(clear);
    const PpField through = b.div("a_v (1 - a_p) scaled", behind, rest, 0, layout.opacity_bits);
    b.release(behind);
    b.release(rest);
    // a <= the maximum code, but the sum's field is a bit wider: narrow it to the opacity's width.
    const PpField sum_a = b.add("matted opacity", a_p, through);
    const PpField a = b.min_const("matted opacity", sum_a, opacity_max);
    b.release(sum_a);
    b.enable_if(a, PpCompare::Greater, 0);
    for (int k = 0; k < 3; ++k) {
        const PpField c_p = emit_polygon_code(b, shape, "polygon colour", k, color_max);
        const PpField c_v = b.load("voxel colour", layout.color_offset(k), layout.color_bits, false);
        const PpField front = b.mul("c_p a_p", c_p, a_p);
        const PpField back = b.mul("c_v a_v (1 - a_p)", c_v, through);
        b.release(c_p);
        b.release(c_v);
        const PpField sum = b.add("colour sum", front, back);
        b.release(front);
        b.release(back);
        const PpField c = b.div("matted colour", sum, a, 0, layout.color_bits);
        b.release(sum);
        b.store(c, layout.color_offset(k), layout.color_bits);
        b.release(c);
    }
    b.store(a, layout.opacity_offset(), layout.opacity_bits);
    b.release(a);
    b.release(through);
}

}  // namespace

PpProgram build_polygon_program(const PolygonProgramShape& shape, const PpProgramInputs& inputs) {
    const VoxelRecordLayout& layout = inputs.layout;
    const std::int64_t opacity_max = (std::int64_t{1} << layout.opacity_bits) - 1;
    PpProgramBuilder b("scan-convert polygon", inputs.local_memory_bits);
    const PpField count = emit_coverage_count(b, shape);
    b.enable_all();
    b.enable_if(count, PpCompare::Greater, 0);

    // The polygon's opacity at this voxel, times coverage: a_p = alpha (count / J).
    const PpField alpha = emit_polygon_code(b, shape, "polygon opacity", 3, opacity_max);
    const PpField weighted = b.mul("opacity x count", alpha, count);
    b.release(alpha);
    const PpField samples_field = b.set_const("J", shape.samples);
    const PpField a_p = b.div("polygon coverage opacity", weighted, samples_field, 0, layout.opacity_bits);
    b.release(weighted);
    b.release(samples_field);
    emit_matte(b, shape, layout, a_p);
    b.release(a_p);
    b.release(count);
    b.enable_all();
    return b.finish();
}

std::vector<QeeCoefficients> polygon_expressions(const PreparedPolygon& polygon, const std::vector<glm::dvec3>& offsets,
                                                 const SlotFrame& frame, const VoxelRecordLayout& layout) {
    std::vector<QeeCoefficients> out;
    const glm::dvec3 origin(frame.origin);
    for (const glm::dvec3& offset : offsets) {
        // The sample point is the voxel centre moved by `offset`.
        out.push_back(linear(polygon.normal, polygon.plane_offset, origin + offset, kScale));
        for (std::size_t i = 0; i < polygon.edge_normals.size(); ++i)
            out.push_back(linear(polygon.edge_normals[i], polygon.edge_offsets[i], origin + offset, kScale));
    }
    const double color_max = static_cast<double>((std::int64_t{1} << layout.color_bits) - 1);
    const double opacity_max = static_cast<double>((std::int64_t{1} << layout.opacity_bits) - 1);
    for (const LinearFunction* f : {&polygon.red, &polygon.green, &polygon.blue}) {
        out.push_back(linear(glm::dvec3(f->gradient), f->offset, origin, kScale * color_max));
    }
    out.push_back(linear(glm::dvec3(polygon.opacity.gradient), polygon.opacity.offset, origin, kScale * opacity_max));
    return out;
}

bool polygon_reaches_slot(const PreparedPolygon& polygon, const SlotFrame& frame, glm::ivec3 dims,
                          const PpArrayShape& shape) {
    if (!frame.used || polygon.degenerate) return false;
    const glm::vec3 lo(frame.origin);
    const glm::vec3 hi = glm::vec3(glm::min(frame.origin + glm::ivec3(shape.columns - 1, shape.rows - 1, 0), dims - 1));
    return glm::all(glm::lessThanEqual(lo, polygon.upper + 1.0f)) &&
           glm::all(glm::greaterThanEqual(hi, polygon.lower - 1.0f));
}

PpProgram build_emptiness_program(const PpProgramInputs& inputs) {
    PpProgramBuilder b("emptiness", inputs.local_memory_bits);
    const PpField opacity = b.load("opacity", inputs.layout.opacity_offset(), inputs.layout.opacity_bits, false);
    const PpField non_empty = b.set_const("non-empty", 0, 1, false);
    b.enable_if(opacity, PpCompare::Greater, 0);
    b.assign_const(non_empty, 1);
    b.enable_all();
    b.release(opacity);
    b.release(non_empty);  // read out by the renderer, as the pyramid's broadcast charges
    return b.finish();
}

int host_coverage(const PreparedPolygon& polygon, const std::vector<glm::dvec3>& offsets, glm::ivec3 voxel) {
    int count = 0;
    for (const glm::dvec3& offset : offsets) count += polygon.in_sheet(glm::dvec3(voxel) + offset) ? 1 : 0;
    return count;
}

}  // namespace pp5
