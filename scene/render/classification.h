#pragma once
// Classification: voxel value (and gradient magnitude) to opacity, and value to base colour.
// Levoy's two opacity functions ("Display of Surfaces from Volume Data", 1988) and a plain
// piecewise-linear transfer function.
//
// Units: values are the volume's own; gradient magnitudes are in value units per voxel (central
// differences over two voxels, halved), which is what Levoy's transition thickness r is measured in.

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace pp5 {

// One isovalue surface: opacity alpha_v at value f_v, fading to 0 over `thickness` voxels (Levoy's r).
struct IsovalueContour {
    float value = 0.0f;
    float opacity = 1.0f;
    float thickness = 1.0f;

    bool operator==(const IsovalueContour&) const = default;
};

// A control point of a region-boundary or piecewise-linear function: (value, opacity).
struct OpacityPoint {
    float value = 0.0f;
    float opacity = 0.0f;

    bool operator==(const OpacityPoint&) const = default;
};

enum class ClassificationKind { IsovalueContours, RegionBoundaries, PiecewiseLinear };

// The three kinds, for f the value and |g| the gradient magnitude:
//  IsovalueContours (Levoy eq. 3), for each contour (f_v, alpha_v, r):
//      alpha = alpha_v                               if |g| = 0 and f = f_v
//      alpha = alpha_v (1 - |f_v - f| / (r |g|))     if |g| > 0 and f - r|g| <= f_v <= f + r|g|
//      alpha = 0                                     otherwise;
//    several contours combine as 1 - prod(1 - alpha_n).
//  RegionBoundaries (Levoy eq. 4): alpha = |g| * (the points' opacities linearly interpolated at f),
//    clamped to [0,1]; 0 outside [first point's value, last point's value]. A gradient-weighted
//    function: flat regions are transparent whatever their value.
//  PiecewiseLinear: the points' opacities linearly interpolated at f, the end points' opacities held
//    beyond the ends (as VTK's transfer functions do), so a ramp from (20,0) to (60,1) leaves
//    everything above 60 opaque. No points: transparent.
// Points must be sorted by value; equal values make a step, and the value at the step takes the
// opacity of the later point.
struct Classification {
    ClassificationKind kind = ClassificationKind::IsovalueContours;
    std::vector<IsovalueContour> contours;  // IsovalueContours: combined as 1 - prod(1 - alpha_n)
    std::vector<OpacityPoint> points;       // RegionBoundaries, PiecewiseLinear: sorted by value

    // Opacity in [0,1] of a voxel with value f and gradient magnitude grad_mag (value units per voxel).
    float opacity(float f, float grad_mag) const;

    // False only if no value in [f_min, f_max] with a gradient magnitude in [0, grad_max] can have a
    // non-zero opacity. Used to skip empty space when classifying interpolated samples, so a block of
    // the volume can be declared empty from its value range without classifying anything.
    bool may_be_nonzero(float f_min, float f_max, float grad_max) const;

    bool operator==(const Classification&) const = default;
};

// Throws pp5::InputError (field "classification.*") for unsorted points, opacities outside [0,1],
// non-positive contour thickness, or non-finite numbers.
void validate_classification(const Classification& classification);

// A colour control point: value -> RGB in [0,1].
struct ColorPoint {
    float value = 0.0f;
    glm::vec3 color{1.0f};

    bool operator==(const ColorPoint&) const = default;
};

// Piecewise-linear value -> base colour (c_p in Levoy's shading formula); constant beyond the ends,
// white when empty. Points sorted by value, as for Classification.
struct ColorMap {
    std::vector<ColorPoint> points;
    glm::vec3 color(float f) const;

    bool operator==(const ColorMap&) const = default;
};

// Throws pp5::InputError (field "color_map.*") for unsorted points or colours outside [0,1].
void validate_color_map(const ColorMap& color_map);

}  // namespace pp5
