// Making the hybrid representation: the minimum filter never overestimates, point selection counts
// what a brute-force pass over the error grid counts, and the counts move with the threshold, the
// error grid and the low-resolution factor as the paper reports (section 5).

#include "kernels/wilson/hybrid_volume.h"
#include "scene/volume/phantoms.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <tuple>

namespace pp5 {
namespace {

WilsonSettings settings(int factor, double threshold, Downsample filter = Downsample::Cubic, int grid = 1) {
    WilsonSettings s;
    s.downsample_factor = factor;
    s.error_threshold = threshold;
    s.downsample = filter;
    s.error_grid_factor = grid;
    return s;
}

TEST(WilsonLowResolution, TheMinimumFilterNeverOverestimates) {
    const Volume v = make_head_phantom(40);
    for (const int k : {2, 3, 4}) {
        const HybridVolume h = HybridVolume::build(v, settings(k, 1.0, Downsample::Minimum), false);
        int over = 0;
        for (int z = 0; z < v.dims().z; ++z)
            for (int y = 0; y < v.dims().y; ++y)
                for (int x = 0; x < v.dims().x; ++x)
                    over +=
                        reconstruct_low_resolution(h.low_resolution(), k, glm::vec3(x, y, z)) > v.at(x, y, z) + 1e-4f
                            ? 1
                            : 0;
        EXPECT_EQ(over, 0) << "k = " << k;
    }
    // The cubic filter does overestimate somewhere (else the test above proves nothing).
    const HybridVolume cubic = HybridVolume::build(v, settings(2, 1.0), false);
    EXPECT_GT(cubic.selection().mean_abs_error, 0.0);
}

TEST(WilsonLowResolution, AFactorOfOneKeepsTheVolume) {
    const Volume v = make_head_phantom(24);
    const HybridVolume h = HybridVolume::build(v, settings(1, 1.0 / 64), false);
    for (std::size_t i = 0; i < v.samples().size(); ++i)
        ASSERT_NEAR(h.low_resolution().samples()[i], v.samples()[i], 1e-3f);
    EXPECT_EQ(h.points().size(), 0u);
}

TEST(WilsonPoints, SelectionCountsWhatABruteForcePassCounts) {
    const Volume v = make_head_phantom(36);
    const double range = v.max_value() - v.min_value();
    for (const double tau : {1.0 / 64, 1.0 / 16, 1.0 / 8}) {
        const HybridVolume h = HybridVolume::build(v, settings(2, tau), false);
        std::uint64_t expected = 0;
        for (int z = 0; z < v.dims().z; ++z)
            for (int y = 0; y < v.dims().y; ++y)
                for (int x = 0; x < v.dims().x; ++x) {
                    const double e =
                        (v.at(x, y, z) - reconstruct_low_resolution(h.low_resolution(), 2, glm::vec3(x, y, z))) / range;
                    expected += std::abs(e) > tau ? 1 : 0;
                }
        EXPECT_EQ(h.points().size(), expected) << "threshold " << tau;
        // Each stored error is the sample's own, to the byte's precision.
        for (const HybridPoint& p : h.points()) {
            const glm::vec3 at = h.position(p);
            const double e = (v.at(p.x, p.y, p.z) - reconstruct_low_resolution(h.low_resolution(), 2, at)) / range;
            ASSERT_NEAR(p.error / 127.0, e, 0.5 / 127 + 1e-6);
        }
    }
}

TEST(WilsonPoints, CountsFallWithTheThresholdAndTheResolutionAndRiseWithTheErrorGrid) {
    const Volume v = make_head_phantom(32);
    std::uint64_t previous = ~std::uint64_t{0};
    for (const double tau : {1.0 / 64, 1.0 / 32, 1.0 / 16, 1.0 / 12, 1.0 / 8}) {
        const std::uint64_t n = HybridVolume::build(v, settings(2, tau), false).points().size();
        EXPECT_LT(n, previous) << "threshold " << tau;
        previous = n;
    }
    const auto count = [&](int k, int grid) {
        return HybridVolume::build(v, settings(k, 1.0 / 32, Downsample::Cubic, grid), false).points().size();
    };
    EXPECT_GT(count(4, 1), count(2, 1));
    EXPECT_GT(count(2, 2), count(2, 1));
}

TEST(WilsonPoints, ABudgetKeepsTheLargestErrorsInStorageOrder) {
    const Volume v = make_head_phantom(32);
    WilsonSettings s = settings(2, 1.0 / 64);
    const HybridVolume all = HybridVolume::build(v, s, false);
    s.max_points = all.points().size() / 4;
    const HybridVolume some = HybridVolume::build(v, s, false);
    ASSERT_EQ(some.points().size(), s.max_points);
    int smallest_kept = 127;
    for (const HybridPoint& p : some.points())
        smallest_kept = std::min(smallest_kept, std::abs(static_cast<int>(p.error)));
    std::uint64_t larger_left_out = 0;
    for (const HybridPoint& p : all.points())
        larger_left_out += std::abs(static_cast<int>(p.error)) > smallest_kept + 1 ? 1 : 0;
    EXPECT_LE(larger_left_out, some.points().size());
    for (std::size_t i = 1; i < some.points().size(); ++i) {
        const HybridPoint& a = some.points()[i - 1];
        const HybridPoint& b = some.points()[i];
        ASSERT_LT(std::tie(a.z, a.y, a.x), std::tie(b.z, b.y, b.x));
    }
}

TEST(WilsonPoints, OnlyUnderestimatesWhenAskedForThePositiveSign) {
    const Volume v = make_head_phantom(32);
    WilsonSettings s = settings(2, 1.0 / 64);
    s.error_sign = ErrorSign::Positive;
    const HybridVolume h = HybridVolume::build(v, s, false);
    ASSERT_GT(h.points().size(), 0u);
    for (const HybridPoint& p : h.points()) ASSERT_GT(p.error, 0);
}

TEST(WilsonPoints, TheSameRepresentationAtOneAndTwoThreads) {
    const Volume v = make_head_phantom(40);
    const auto build = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        return HybridVolume::build(v, settings(2, 1.0 / 64, Downsample::Cubic, 2), true);
    };
    const HybridVolume one = build(1), two = build(2);
    ASSERT_EQ(one.points().size(), two.points().size());
    for (std::size_t i = 0; i < one.points().size(); ++i) {
        const HybridPoint &a = one.points()[i], &b = two.points()[i];
        ASSERT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z && a.value == b.value && a.error == b.error &&
                    a.normal == b.normal && a.gradient == b.gradient);
    }
    EXPECT_EQ(std::vector<float>(one.low_resolution().samples().begin(), one.low_resolution().samples().end()),
              std::vector<float>(two.low_resolution().samples().begin(), two.low_resolution().samples().end()));
}

TEST(WilsonNormals, TheTableCoversTheSphereEvenly) {
    const NormalTable& t = NormalTable::get();
    // Every unit vector is within about 12.7 degrees (the lattice's spacing) of some direction.
    double worst = 1.0;
    for (int i = 0; i < 2000; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / 2000.0, r = std::sqrt(1 - z * z), phi = 2.399963 * i * 1.37;
        const glm::vec3 n(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                          static_cast<float>(z));
        worst = std::min(worst, static_cast<double>(glm::dot(n, t.direction(t.nearest(n)))));
    }
    EXPECT_GT(worst, std::cos(12.7 * 3.14159265 / 180.0));
    EXPECT_EQ(t.nearest(glm::vec3(0.0f)), NormalTable::kNone);
    EXPECT_EQ(t.direction(NormalTable::kNone), glm::vec3(0.0f));
}

}  // namespace
}  // namespace pp5
