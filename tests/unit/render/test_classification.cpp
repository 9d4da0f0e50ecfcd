#include "scene/render/classification.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace pp5 {
namespace {

Classification contours(std::vector<IsovalueContour> list) {
    Classification c;
    c.kind = ClassificationKind::IsovalueContours;
    c.contours = std::move(list);
    return c;
}

Classification regions(std::vector<OpacityPoint> points) {
    Classification c;
    c.kind = ClassificationKind::RegionBoundaries;
    c.points = std::move(points);
    return c;
}

Classification piecewise(std::vector<OpacityPoint> points) {
    Classification c;
    c.kind = ClassificationKind::PiecewiseLinear;
    c.points = std::move(points);
    return c;
}

TEST(IsovalueContour, FullOpacityAtTheIsovalue) {
    const Classification c = contours({{100.0f, 0.8f, 2.0f}});
    EXPECT_FLOAT_EQ(c.opacity(100.0f, 0.0f), 0.8f);  // |grad| = 0 and f = f_v
    EXPECT_FLOAT_EQ(c.opacity(100.0f, 10.0f), 0.8f);
    EXPECT_FLOAT_EQ(c.opacity(100.5f, 0.0f), 0.0f);  // flat, off the isovalue
}

TEST(IsovalueContour, FadesLinearlyToTheEdgeOfTheTransition) {
    // r = 2 voxels, |grad| = 10 per voxel: the fade spans 20 value units either side.
    const Classification c = contours({{100.0f, 0.8f, 2.0f}});
    EXPECT_NEAR(c.opacity(110.0f, 10.0f), 0.4f, 1e-6f);  // 0.8 (1 - 10/20)
    EXPECT_NEAR(c.opacity(85.0f, 10.0f), 0.2f, 1e-6f);   // 0.8 (1 - 15/20)
    EXPECT_NEAR(c.opacity(120.0f, 10.0f), 0.0f, 1e-7f);  // at the edge
    EXPECT_EQ(c.opacity(120.5f, 10.0f), 0.0f);           // beyond it
    EXPECT_EQ(c.opacity(79.0f, 10.0f), 0.0f);
}

TEST(IsovalueContour, SeveralCombineAsOneMinusProductOfTransparencies) {
    const Classification c = contours({{100.0f, 0.5f, 1.0f}, {104.0f, 0.6f, 1.0f}});
    // f = 102, |grad| = 4: each contour is 2 units away with a reach of 4: half its opacity.
    const float a1 = 0.5f * 0.5f;
    const float a2 = 0.6f * 0.5f;
    EXPECT_NEAR(c.opacity(102.0f, 4.0f), 1.0f - (1.0f - a1) * (1.0f - a2), 1e-6f);
    EXPECT_EQ(contours({}).opacity(50.0f, 3.0f), 0.0f);
}

TEST(RegionBoundaries, GradientTimesInterpolatedOpacity) {
    const Classification c = regions({{0.0f, 0.0f}, {100.0f, 0.5f}, {200.0f, 1.0f}});
    EXPECT_NEAR(c.opacity(50.0f, 0.4f), 0.4f * 0.25f, 1e-6f);
    EXPECT_NEAR(c.opacity(150.0f, 1.0f), 0.75f, 1e-6f);
    EXPECT_EQ(c.opacity(150.0f, 0.0f), 0.0f);   // flat regions are transparent
    EXPECT_EQ(c.opacity(150.0f, 10.0f), 1.0f);  // clamped
    EXPECT_EQ(c.opacity(-1.0f, 1.0f), 0.0f);    // outside the points' range
    EXPECT_EQ(c.opacity(201.0f, 1.0f), 0.0f);
    EXPECT_NEAR(c.opacity(200.0f, 0.5f), 0.5f, 1e-6f);  // the last point itself is inside
}

TEST(PiecewiseLinear, InterpolatesAndHoldsTheEnds) {
    const Classification ramp = piecewise({{20.0f, 0.0f}, {60.0f, 1.0f}});
    EXPECT_EQ(ramp.opacity(10.0f, 5.0f), 0.0f);
    EXPECT_NEAR(ramp.opacity(30.0f, 0.0f), 0.25f, 1e-6f);
    EXPECT_EQ(ramp.opacity(60.0f, 0.0f), 1.0f);
    EXPECT_EQ(ramp.opacity(250.0f, 0.0f), 1.0f);  // held above the last point
    EXPECT_EQ(piecewise({}).opacity(30.0f, 0.0f), 0.0f);
    // Equal values make a step; the value at the step takes the later point.
    const Classification step = piecewise({{0.0f, 0.1f}, {10.0f, 0.1f}, {10.0f, 0.9f}, {20.0f, 0.9f}});
    EXPECT_NEAR(step.opacity(9.999f, 0.0f), 0.1f, 1e-6f);
    EXPECT_NEAR(step.opacity(10.0f, 0.0f), 0.9f, 1e-6f);
}

// may_be_nonzero must never say "empty" where opacity() can be non-zero: check on a grid of values and
// gradients inside random ranges.
TEST(Classification, MayBeNonzeroIsConservative) {
    const std::vector<Classification> functions = {
        contours({{60.0f, 1.0f, 1.0f}, {140.0f, 0.5f, 2.5f}}),
        regions({{20.0f, 0.0f}, {80.0f, 0.7f}, {120.0f, 0.0f}}),
        piecewise({{20.0f, 0.0f}, {60.0f, 1.0f}}),
        piecewise({{50.0f, 0.0f}, {70.0f, 0.6f}, {90.0f, 0.0f}}),
    };
    std::uint32_t seed = 12345;
    auto next = [&]() {
        seed = seed * 1664525u + 1013904223u;
        return static_cast<float>(seed >> 8) / static_cast<float>(1u << 24);
    };
    for (const Classification& c : functions) {
        int empty_ranges = 0;
        for (int trial = 0; trial < 2000; ++trial) {
            const float lo = 200.0f * next();
            const float hi = lo + 30.0f * next();
            const float grad_max = trial % 5 == 0 ? 0.0f : 20.0f * next();
            if (c.may_be_nonzero(lo, hi, grad_max)) continue;
            ++empty_ranges;
            for (int i = 0; i <= 20; ++i) {
                const float f = lo + (hi - lo) * static_cast<float>(i) / 20.0f;
                for (int j = 0; j <= 10; ++j) {
                    const float g = grad_max * static_cast<float>(j) / 10.0f;
                    ASSERT_EQ(c.opacity(f, g), 0.0f) << "f " << f << " g " << g << " range " << lo << ".." << hi;
                }
            }
        }
        EXPECT_GT(empty_ranges, 0);  // the test exercised the "empty" answer
    }
}

TEST(Classification, ValidationRejectsBadInput) {
    EXPECT_NO_THROW(validate_classification(piecewise({{0.0f, 0.0f}, {1.0f, 1.0f}})));
    EXPECT_THROW(validate_classification(piecewise({{1.0f, 0.0f}, {0.0f, 1.0f}})), InputError);
    EXPECT_THROW(validate_classification(piecewise({{0.0f, 1.5f}})), InputError);
    EXPECT_THROW(validate_classification(contours({{10.0f, 1.0f, 0.0f}})), InputError);
    EXPECT_THROW(validate_color_map(ColorMap{{{0.0f, {2.0f, 0.0f, 0.0f}}}}), InputError);
}

TEST(ColorMap, WhiteWhenEmptyOtherwisePiecewiseLinear) {
    EXPECT_EQ(ColorMap{}.color(123.0f), glm::vec3(1.0f));
    const ColorMap map{{{0.0f, {1.0f, 0.0f, 0.0f}}, {100.0f, {0.0f, 0.0f, 1.0f}}}};
    EXPECT_EQ(map.color(-5.0f), glm::vec3(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(map.color(500.0f), glm::vec3(0.0f, 0.0f, 1.0f));
    const glm::vec3 quarter = map.color(25.0f);
    EXPECT_NEAR(quarter.r, 0.75f, 1e-6f);
    EXPECT_NEAR(quarter.b, 0.25f, 1e-6f);
}

}  // namespace
}  // namespace pp5
