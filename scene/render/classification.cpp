#include "scene/render/classification.h"

#include "sim/core/input_error.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace pp5 {

namespace {

// Where a value falls among sorted control points: between `lower` and `upper` with weights that sum
// to one (Levoy's eq. 4 form, exact at both points), or beyond either end.
struct Bracket {
    enum class Where { Below, Inside, Above } where = Where::Below;
    std::size_t lower = 0;
    std::size_t upper = 0;
    float lower_weight = 1.0f;
    float upper_weight = 0.0f;
};

template <class Point>
Bracket bracket(std::span<const Point> points, float f) {
    Bracket b;
    if (points.empty() || !(f >= points.front().value)) return b;  // NaN counts as below
    const std::size_t last = points.size() - 1;
    if (f >= points[last].value) {
        b.lower = b.upper = last;
        b.where = f == points[last].value ? Bracket::Where::Inside : Bracket::Where::Above;
        return b;
    }
    // The first point above f; equal values (a step) resolve to the later point.
    const auto above =
        std::upper_bound(points.begin(), points.end(), f, [](float value, const Point& p) { return value < p.value; });
    b.where = Bracket::Where::Inside;
    b.upper = static_cast<std::size_t>(above - points.begin());
    b.lower = b.upper - 1;
    const float f_lower = points[b.lower].value;
    const float f_upper = points[b.upper].value;
    const float width = f_upper - f_lower;  // > 0: f_lower <= f < f_upper
    b.upper_weight = (f - f_lower) / width;
    b.lower_weight = (f_upper - f) / width;
    return b;
}

// The points' opacities interpolated at f; beyond the ends the end opacities (clamped) or 0.
float interpolate_opacity(std::span<const OpacityPoint> points, float f, bool hold_ends) {
    const Bracket b = bracket(points, f);
    switch (b.where) {
        case Bracket::Where::Below: return hold_ends && !points.empty() ? points.front().opacity : 0.0f;
        case Bracket::Where::Above: return hold_ends ? points.back().opacity : 0.0f;
        case Bracket::Where::Inside: break;
    }
    return points[b.upper].opacity * b.upper_weight + points[b.lower].opacity * b.lower_weight;
}

// The largest interpolated opacity over [lo, hi]: a piecewise-linear function peaks at an end of the
// interval or at a control point inside it.
float max_opacity_over(std::span<const OpacityPoint> points, float lo, float hi, bool hold_ends) {
    float peak = std::max(interpolate_opacity(points, lo, hold_ends), interpolate_opacity(points, hi, hold_ends));
    for (const OpacityPoint& p : points) {
        if (p.value >= lo && p.value <= hi) peak = std::max(peak, p.opacity);
    }
    return peak;
}

float contour_opacity(const IsovalueContour& contour, float f, float grad_mag) {
    if (grad_mag <= 0.0f) return f == contour.value ? contour.opacity : 0.0f;
    const float reach = contour.thickness * grad_mag;  // r |grad|: how far in value the fade extends
    if (f - reach <= contour.value && contour.value <= f + reach) {
        return contour.opacity * (1.0f - std::abs(contour.value - f) / reach);
    }
    return 0.0f;
}

bool is_unit_interval(float x) { return x >= 0.0f && x <= 1.0f; }

template <class Point>
void check_sorted(std::span<const Point> points, const std::string& field) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!std::isfinite(points[i].value))
            reject_field(field + "[" + std::to_string(i) + "].value", "must be finite");
        if (i > 0 && points[i].value < points[i - 1].value) {
            reject_field(field + "[" + std::to_string(i) + "].value", "points must be sorted by value");
        }
    }
}

}  // namespace

float Classification::opacity(float f, float grad_mag) const {
    switch (kind) {
        case ClassificationKind::IsovalueContours: {
            float transparency = 1.0f;
            for (const IsovalueContour& contour : contours)
                transparency *= 1.0f - contour_opacity(contour, f, grad_mag);
            return std::clamp(1.0f - transparency, 0.0f, 1.0f);
        }
        case ClassificationKind::RegionBoundaries: {
            const float base = interpolate_opacity(points, f, /*hold_ends=*/false);
            return std::clamp(grad_mag * base, 0.0f, 1.0f);
        }
        case ClassificationKind::PiecewiseLinear:
            return std::clamp(interpolate_opacity(points, f, /*hold_ends=*/true), 0.0f, 1.0f);
    }
    return 0.0f;
}

bool Classification::may_be_nonzero(float f_min, float f_max, float grad_max) const {
    switch (kind) {
        case ClassificationKind::IsovalueContours:
            for (const IsovalueContour& contour : contours) {
                if (contour.opacity <= 0.0f) continue;
                // Distance in value from the isovalue to the range; the fade reaches r |grad| at most.
                const float distance = std::max({0.0f, f_min - contour.value, contour.value - f_max});
                if (distance == 0.0f || distance <= contour.thickness * grad_max) return true;
            }
            return false;
        case ClassificationKind::RegionBoundaries: {
            if (grad_max <= 0.0f || points.empty()) return false;
            const float lo = std::max(f_min, points.front().value);
            const float hi = std::min(f_max, points.back().value);
            return lo <= hi && max_opacity_over(points, lo, hi, /*hold_ends=*/false) > 0.0f;
        }
        case ClassificationKind::PiecewiseLinear:
            return max_opacity_over(points, f_min, f_max, /*hold_ends=*/true) > 0.0f;
    }
    return true;
}

void validate_classification(const Classification& classification) {
    for (std::size_t i = 0; i < classification.contours.size(); ++i) {
        const IsovalueContour& c = classification.contours[i];
        const std::string field = "classification.contours[" + std::to_string(i) + "]";
        if (!std::isfinite(c.value)) reject_field(field + ".value", "must be finite");
        if (!is_unit_interval(c.opacity)) reject_field(field + ".opacity", "must lie in [0, 1]");
        if (!(c.thickness > 0.0f && std::isfinite(c.thickness))) reject_field(field + ".thickness", "must be positive");
    }
    const std::span<const OpacityPoint> points = classification.points;
    check_sorted(points, "classification.points");
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!is_unit_interval(points[i].opacity)) {
            reject_field("classification.points[" + std::to_string(i) + "].opacity", "must lie in [0, 1]");
        }
    }
}

glm::vec3 ColorMap::color(float f) const {
    if (points.empty()) return glm::vec3(1.0f);
    const Bracket b = bracket(std::span<const ColorPoint>(points), f);
    switch (b.where) {
        case Bracket::Where::Below: return points.front().color;
        case Bracket::Where::Above: return points.back().color;
        case Bracket::Where::Inside: break;
    }
    return points[b.upper].color * b.upper_weight + points[b.lower].color * b.lower_weight;
}

void validate_color_map(const ColorMap& color_map) {
    const std::span<const ColorPoint> points = color_map.points;
    check_sorted(points, "color_map.points");
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::vec3 c = points[i].color;
        if (!is_unit_interval(c.r) || !is_unit_interval(c.g) || !is_unit_interval(c.b)) {
            reject_field("color_map.points[" + std::to_string(i) + "].color", "components must lie in [0, 1]");
        }
    }
}

}  // namespace pp5
