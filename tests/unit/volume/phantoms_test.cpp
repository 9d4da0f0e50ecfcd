// Phantoms: the geometry their header promises, which other modules' tests rely on.

#include "scene/volume/phantoms.h"
#include "sim/core/input_error.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>

namespace pp5 {
namespace {

using ::testing::HasSubstr;

std::size_t count_above(const Volume& v, float threshold) {
    std::size_t n = 0;
    for (const float s : v.samples()) n += s > threshold ? 1u : 0u;
    return n;
}

double ball_volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

TEST(SpherePhantom, VoxelsAboveHalfValueFillTheBall) {
    for (const int n : {64, 127}) {
        const Volume v = make_sphere_phantom(n);
        EXPECT_EQ(v.dims(), glm::ivec3(n));
        EXPECT_EQ(v.source_type(), ScalarType::UInt8);
        const double expected = ball_volume(0.35 * n);
        EXPECT_NEAR(static_cast<double>(count_above(v, 100.0f)), expected, 0.02 * expected) << n;
        EXPECT_EQ(v.max_value(), 200.0f);
        EXPECT_EQ(v.min_value(), 0.0f);
    }
}

TEST(SpherePhantom, HalfValueLiesExactlyAtTheDocumentedRadius) {
    const int n = 41;                                        // centre (20, 20, 20)
    const Volume v = make_sphere_phantom(n, 10.0f / 41.0f);  // radius 10 voxels
    EXPECT_NEAR(v.at(30, 20, 20), 100.0f, 1e-3f);
    EXPECT_NEAR(v.at(20, 10, 20), 100.0f, 1e-3f);
    EXPECT_NEAR(v.at(20, 20, 30), 100.0f, 1e-3f);
    EXPECT_EQ(v.at(29, 20, 20), 200.0f);
    EXPECT_EQ(v.at(31, 20, 20), 0.0f);
    EXPECT_EQ(v.at(20, 20, 20), 200.0f);
    EXPECT_NEAR(v.at(26, 28, 20), 100.0f, 1e-3f);  // (6, 8, 0) from the centre: distance 10
}

TEST(SpherePhantom, IsSymmetricAboutTheGridCentre) {
    const int n = 32;
    const Volume v = make_sphere_phantom(n);
    for (int z = 0; z < n; z += 3) {
        for (int y = 0; y < n; y += 2) {
            for (int x = 0; x < n; ++x) {
                EXPECT_EQ(v.at(x, y, z), v.at(n - 1 - x, y, z));
                EXPECT_EQ(v.at(x, y, z), v.at(x, n - 1 - y, n - 1 - z));
                EXPECT_FLOAT_EQ(v.at(x, y, z), v.at(y, x, z));
            }
        }
    }
}

TEST(SpherePhantom, EdgeIsRampedNotStepped) {
    const Volume v = make_sphere_phantom(48);
    std::size_t partial = 0;
    for (const float s : v.samples()) partial += (s > 0.0f && s < 200.0f) ? 1u : 0u;
    // A one-voxel shell of the sphere's surface: about 4 pi r^2 voxels.
    const double shell = 4.0 * std::numbers::pi * (0.35 * 48) * (0.35 * 48);
    EXPECT_NEAR(static_cast<double>(partial), shell, 0.15 * shell);
}

TEST(SpherePhantom, IsDeterministic) {
    const Volume a = make_sphere_phantom(33, 0.3f);
    const Volume b = make_sphere_phantom(33, 0.3f);
    EXPECT_TRUE(std::equal(a.samples().begin(), a.samples().end(), b.samples().begin()));
}

TEST(SpherePhantom, RejectsBadArguments) {
    EXPECT_THROW(make_sphere_phantom(0), std::invalid_argument);
    EXPECT_THROW(make_sphere_phantom(8, 0.0f), std::invalid_argument);
}

TEST(CheckerBoxPhantom, EveryOneOfTheMillionVoxelsIsNonEmpty) {
    const Volume v = make_checker_box_phantom();
    EXPECT_EQ(v.dims(), glm::ivec3(100));
    EXPECT_EQ(v.voxel_count(), 1000000u);
    EXPECT_EQ(count_above(v, 0.0f), 1000000u);
    EXPECT_EQ(count_above(v, 150.0f), 500000u);
    EXPECT_EQ(v.min_value(), 100.0f);
    EXPECT_EQ(v.max_value(), 200.0f);
}

TEST(CheckerBoxPhantom, CubesAlternateAcrossEveryCellFace) {
    const int n = 100;
    const int cell = 10;
    const Volume v = make_checker_box_phantom(n, cell);
    EXPECT_EQ(v.at(0, 0, 0), 200.0f);
    EXPECT_EQ(v.at(9, 9, 9), 200.0f);
    EXPECT_EQ(v.at(10, 0, 0), 100.0f);
    EXPECT_EQ(v.at(10, 10, 0), 200.0f);
    EXPECT_EQ(v.at(10, 10, 10), 100.0f);
    std::size_t mismatches = 0;
    for (int z = 0; z < n; ++z) {
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x + 1 < n; ++x) {
                const bool crosses = (x + 1) % cell == 0;
                mismatches += (v.at(x, y, z) != v.at(x + 1, y, z)) != crosses;
                mismatches += (v.at(y, x, z) != v.at(y, x + 1, z)) != crosses;
                mismatches += (v.at(y, z, x) != v.at(y, z, x + 1)) != crosses;
            }
        }
    }
    EXPECT_EQ(mismatches, 0u);
}

TEST(CheckerBoxPhantom, OtherSizes) {
    const Volume v = make_checker_box_phantom(7, 3);
    EXPECT_EQ(v.dims(), glm::ivec3(7));
    EXPECT_EQ(v.at(2, 0, 0), 200.0f);
    EXPECT_EQ(v.at(3, 0, 0), 100.0f);
    EXPECT_EQ(v.at(6, 6, 6), 200.0f);  // cell (2, 2, 2)
    EXPECT_THROW(make_checker_box_phantom(10, 0), std::invalid_argument);
}

TEST(HeadPhantom, HasItsLayersFromOutsideIn) {
    const int n = 96;
    const Volume v = make_head_phantom(n);
    EXPECT_EQ(v.dims(), glm::ivec3(n));
    EXPECT_EQ(v.source_type(), ScalarType::UInt8);
    const float c = 0.5f * static_cast<float>(n - 1);
    const float unit = 0.5f * static_cast<float>(n);
    const int mid = n / 2;
    // Along +x through the centre, at fractions of n/2 between the documented semi-axes.
    const auto along_x = [&](float f) { return v.at(static_cast<int>(std::lround(c + f * unit)), mid, mid); };
    EXPECT_EQ(along_x(0.95f), 0.0f);    // outside
    EXPECT_EQ(along_x(0.67f), 60.0f);   // skin: 0.64 .. 0.70
    EXPECT_EQ(along_x(0.60f), 220.0f);  // skull: 0.56 .. 0.64
    EXPECT_EQ(along_x(0.30f), 110.0f);  // brain
    // Along +y (front), where the semi-axes are longer.
    EXPECT_EQ(v.at(mid, static_cast<int>(std::lround(c + 0.85f * unit)), mid), 60.0f);
    EXPECT_EQ(v.at(mid, static_cast<int>(std::lround(c + 0.78f * unit)), mid), 220.0f);
    // The ventricles' centres.
    for (const float side : {-0.11f, 0.11f}) {
        const auto at = [&](float offset) { return static_cast<int>(std::lround(c + offset * unit)); };
        EXPECT_EQ(v.at(at(side), at(0.02f), at(0.08f)), 30.0f) << side;
    }
    EXPECT_EQ(v.min_value(), 0.0f);
    EXPECT_EQ(v.max_value(), 220.0f);
}

TEST(HeadPhantom, IsMirrorSymmetricAndSmooth) {
    const int n = 64;
    const Volume v = make_head_phantom(n);
    std::set<float> levels{0.0f, 30.0f, 60.0f, 110.0f, 220.0f};
    std::size_t between = 0;
    for (int z = 0; z < n; ++z) {
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
                EXPECT_NEAR(v.at(x, y, z), v.at(n - 1 - x, y, z), 1e-3f);
                between += levels.count(v.at(x, y, z)) == 0 ? 1u : 0u;
            }
        }
    }
    EXPECT_GT(between, 1000u);  // ramped boundaries, not a staircase
}

TEST(ConstantVolume, IsFloat32AndConstant) {
    const Volume v = make_constant_volume({5, 7, 3}, 42.5f);
    EXPECT_EQ(v.dims(), glm::ivec3(5, 7, 3));
    EXPECT_EQ(v.source_type(), ScalarType::Float32);
    EXPECT_EQ(v.min_value(), 42.5f);
    EXPECT_EQ(v.max_value(), 42.5f);
    EXPECT_EQ(v.voxel_count(), 105u);
}

TEST(MakePhantom, MapsNamesToGenerators) {
    EXPECT_EQ(make_phantom("sphere", 17).name(), "sphere");
    EXPECT_EQ(make_phantom("checker-box", 20).name(), "checker-box");
    EXPECT_EQ(make_phantom("head", 16).name(), "head");
    EXPECT_EQ(make_phantom("head", 16).dims(), glm::ivec3(16));
    EXPECT_EQ(phantom_names().size(), 3u);
    for (const auto name : phantom_names()) EXPECT_EQ(make_phantom(name, 9).dims(), glm::ivec3(9)) << name;
}

TEST(MakePhantom, UnknownNameListsTheKnownOnes) {
    try {
        make_phantom("teapot", 32);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "phantom");
        EXPECT_THAT(e.reason(), HasSubstr("teapot"));
        EXPECT_THAT(e.reason(), HasSubstr("sphere, checker-box, head"));
    }
}

TEST(MakePhantom, SizeOutOfRange) {
    try {
        make_phantom("sphere", 0);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "size");
    }
    EXPECT_THROW(make_phantom("head", 5000), InputError);
}

}  // namespace
}  // namespace pp5
