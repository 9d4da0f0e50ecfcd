// resample: trilinear, cell-centred, extent-preserving.

#include "scene/volume/resample.h"
#include "scene/volume/phantoms.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pp5 {
namespace {

using namespace pp5::test;

Volume ramp_volume(glm::ivec3 dims, glm::vec3 spacing) {
    auto samples = pattern(dims, [](int x, int y, int z) {
        return 2.0f * static_cast<float>(x) + 3.0f * static_cast<float>(y) - static_cast<float>(z) + 5.0f;
    });
    return Volume(dims, spacing, ScalarType::Int16, std::move(samples), "ramp");
}

// Where target index j reads on a source axis, before clamping (the documented mapping).
double source_coordinate(int j, int source_n, int target_n) { return (j + 0.5) * source_n / target_n - 0.5; }

TEST(Resample, PreservesAConstantVolumeExactly) {
    const Volume source = make_constant_volume({10, 12, 7}, 37.25f);
    const Volume out = resample(source, {23, 5, 16});
    EXPECT_EQ(out.dims(), glm::ivec3(23, 5, 16));
    for (const float s : out.samples()) ASSERT_EQ(s, 37.25f);
}

TEST(Resample, ReproducesALinearRampInTheInterior) {
    const glm::ivec3 dims{16, 16, 16};
    const Volume source = ramp_volume(dims, glm::vec3(1.0f));
    const glm::ivec3 target{40, 24, 9};
    const Volume out = resample(source, target);
    std::size_t checked = 0;
    for (int z = 0; z < target.z; ++z) {
        for (int y = 0; y < target.y; ++y) {
            for (int x = 0; x < target.x; ++x) {
                const double sx = source_coordinate(x, dims.x, target.x);
                const double sy = source_coordinate(y, dims.y, target.y);
                const double sz = source_coordinate(z, dims.z, target.z);
                const bool interior =
                    sx >= 0 && sx <= dims.x - 1 && sy >= 0 && sy <= dims.y - 1 && sz >= 0 && sz <= dims.z - 1;
                if (!interior) continue;
                ++checked;
                EXPECT_NEAR(out.at(x, y, z), 2 * sx + 3 * sy - sz + 5, 1e-4) << x << " " << y << " " << z;
            }
        }
    }
    EXPECT_GT(checked, 7000u);
}

TEST(Resample, ClampsAtTheEdges) {
    const Volume source = ramp_volume({4, 1, 1}, glm::vec3(1.0f));
    const Volume out = resample(source, {8, 1, 1});
    // Target 0 reads source -0.25, clamped to 0; target 7 reads 3.25, clamped to 3.
    EXPECT_EQ(out.at(0, 0, 0), source.at(0, 0, 0));
    EXPECT_EQ(out.at(7, 0, 0), source.at(3, 0, 0));
    EXPECT_FLOAT_EQ(out.at(1, 0, 0), 5.0f + 2.0f * 0.25f);
}

TEST(Resample, ScalesSpacingSoTheExtentStays) {
    const Volume source = ramp_volume({16, 16, 16}, {1.0f, 2.0f, 0.5f});
    const Volume out = resample(source, {32, 8, 16});
    EXPECT_EQ(out.spacing(), glm::vec3(0.5f, 4.0f, 0.5f));
    EXPECT_EQ(out.physical_extent(), source.physical_extent());
    EXPECT_EQ(out.source_type(), ScalarType::Int16);
    EXPECT_EQ(out.name(), "ramp");
}

TEST(Resample, SameDimsIsAnExactCopy) {
    const Volume source = make_head_phantom(21);
    const Volume out = resample(source, source.dims());
    EXPECT_EQ(samples_of(out), samples_of(source));
    EXPECT_EQ(out.spacing(), source.spacing());
}

TEST(Resample, HalvingAveragesEachTwoByTwoByTwoBlock) {
    const glm::ivec3 dims{6, 4, 8};
    auto samples =
        pattern(dims, [](int x, int y, int z) { return static_cast<float>((x * 37 + y * 11 + z * 5) % 23); });
    const Volume source(dims, glm::vec3(1.0f), ScalarType::UInt8, samples);
    const Volume out = resample(source, dims / 2);
    for (int z = 0; z < dims.z / 2; ++z) {
        for (int y = 0; y < dims.y / 2; ++y) {
            for (int x = 0; x < dims.x / 2; ++x) {
                float sum = 0.0f;
                for (int k = 0; k < 8; ++k) sum += source.at(2 * x + (k & 1), 2 * y + ((k >> 1) & 1), 2 * z + (k >> 2));
                EXPECT_NEAR(out.at(x, y, z), sum / 8.0f, 1e-4f);
            }
        }
    }
    EXPECT_EQ(out.spacing(), glm::vec3(2.0f));
}

TEST(Resample, OddSizesAndDeterminism) {
    const Volume source = make_sphere_phantom(27);
    const Volume a = resample(source, {13, 31, 5});
    const Volume b = resample(source, {13, 31, 5});
    EXPECT_EQ(samples_of(a), samples_of(b));
    EXPECT_EQ(a.dims(), glm::ivec3(13, 31, 5));
    EXPECT_LE(a.max_value(), 200.0f);
    EXPECT_GE(a.min_value(), 0.0f);
    EXPECT_GT(a.max_value(), 150.0f);
}

TEST(Resample, RejectsEmptyInputAndBadTargets) {
    EXPECT_THROW(resample(Volume(), {4, 4, 4}), std::invalid_argument);
    EXPECT_THROW(resample(make_constant_volume({2, 2, 2}, 1.0f), {4, 0, 4}), std::invalid_argument);
}

}  // namespace
}  // namespace pp5
