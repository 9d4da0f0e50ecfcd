// Each region program's functional twin against the program itself run on a PP array: random splats
// (both indices, both blends), points and band composites, drawn one after another into the same
// region state, must leave every PP's accumulators and sheet bit for bit as the twins leave them,
// including the PPs outside each primitive's box (which the twins never visit).

#include "kernels/yuan/screen_primitives.h"

#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <random>

namespace pp5 {
namespace {

constexpr int kSize = 48;  // a small region: 48 x 48 PPs

Camera perspective_camera() {
    Camera c;
    c.projection = Projection::Perspective;
    c.eye = {0, 0, 0};
    c.target = {0, 0, 1};
    c.up = {0, 1, 0};
    c.fov_y_degrees = 40.0f;
    return c;
}

void expect_same_state(const PpArray& array, const PpProgram& program, const RegionPixels& twin,
                       const std::string& after) {
    // The region state is the first eight fields of every region program.
    for (int f = 0; f < 8; ++f) {
        const auto values = array.field_values(program.fields[static_cast<std::size_t>(f)]);
        const std::vector<std::int32_t>& expected = f < 3 ? twin.color[f] : f == 3 ? twin.alpha : twin.sheet[f - 4];
        int differing = 0;
        for (std::size_t p = 0; p < expected.size(); ++p) differing += values[p] != expected[p] ? 1 : 0;
        ASSERT_EQ(differing, 0) << program.field_names[static_cast<std::size_t>(f)] << " after " << after;
    }
}

struct Case {
    SplatIndexMode mode;
    SplatBlend blend;
};

class RegionTwins : public ::testing::TestWithParam<Case> {};

TEST_P(RegionTwins, TwinsMatchTheProgramsOnAPpArray) {
    const Case c = GetParam();
    const RegionFormat format{12, 6};
    const RegionPrograms programs(format, c.mode, c.blend, 208);
    const bool exact = c.mode == SplatIndexMode::Exact;
    const GaussianFootprint kernel(0.7, 2.0);
    const FootprintTables tables(kernel, format.table_bits, format.accumulator_bits, 0.01, !exact);
    const ScreenProjection projection(perspective_camera(), 160, 160);
    // The region starts at screen (40, 56): primitives near it, some crossing its edges.
    const int ox = 40, oy = 56;
    PpArray array(kSize, kSize, 208, 64);
    RegionPixels twin(kSize, kSize);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int splats = 0, points = 0;
    for (int k = 0; k < 60; ++k) {
        const glm::vec4 rgba(static_cast<float>(unit(random)), static_cast<float>(unit(random)),
                             static_cast<float>(unit(random)), static_cast<float>(0.05 + 0.9 * unit(random)));
        const double depth = 20 + 60 * unit(random);
        // Somewhere over the region in screen terms, a little beyond its edges.
        const double sx = ox - 8 + (kSize + 16) * unit(random), sy = oy - 8 + (kSize + 16) * unit(random);
        const glm::dvec2 pp = projection.principal_point();
        const double f = projection.focal_pixels();
        const glm::dvec3 eye{(sx - pp.x) * depth / f, (pp.y - sy) * depth / f, depth};
        if (k % 3 != 2) {
            const auto splat =
                splat_primitive(projection, eye, 1.0 + 2.0 * unit(random), rgba, tables, exact, format, 160, 160);
            ASSERT_TRUE(splat.has_value());
            if (!splat->visible()) continue;
            const SplatDraw draw = splat_draw(*splat, ox, oy, exact);
            const PpTable& table = tables.table(draw.table);
            const PpProgram program = programs.splat(table);
            array.run(program, PpSlotContext{0, draw.expressions});
            draw_splat(twin, draw, table, format, c.mode, c.blend);
            expect_same_state(array, program, twin, "splat " + std::to_string(k));
            ++splats;
        } else {
            const ScreenPrimitive point =
                point_primitive(projection, eye, 0.2 + 0.8 * unit(random), rgba, 1.2 + unit(random), format, 160, 160);
            const PointDraw draw = point_draw(point, ox, oy);
            const PpProgram program = programs.point();
            array.run(program, PpSlotContext{0, draw.expressions});
            draw_point(twin, draw, format);
            expect_same_state(array, program, twin, "point " + std::to_string(k));
            ++points;
        }
        if (k % 10 == 9) {
            const PpProgram program = programs.band_composite();
            array.run(program, PpSlotContext{});
            composite_band(twin, format);
            expect_same_state(array, program, twin, "band composite " + std::to_string(k));
        }
    }
    EXPECT_GT(splats, 20);
    EXPECT_GT(points, 10);
    // Something was drawn: the test compares real values, not zeros.
    std::int64_t total = 0;
    for (const auto a : twin.alpha) total += a;
    EXPECT_GT(total, 0);
}

INSTANTIATE_TEST_SUITE_P(Modes, RegionTwins,
                         ::testing::Values(Case{SplatIndexMode::Affine, SplatBlend::Over},
                                           Case{SplatIndexMode::Affine, SplatBlend::Sheet},
                                           Case{SplatIndexMode::Exact, SplatBlend::Over},
                                           Case{SplatIndexMode::Exact, SplatBlend::Sheet}));

TEST(RegionPrograms, FitTheRenderersLocalMemory) {
    const RegionFormat format{12, 6};
    const GaussianFootprint kernel(0.7, 2.0);
    const FootprintTables tables(kernel, 6, 12, 0.01, true);
    for (const auto mode : {SplatIndexMode::Affine, SplatIndexMode::Exact})
        for (const auto blend : {SplatBlend::Over, SplatBlend::Sheet}) {
            const RegionPrograms programs(format, mode, blend, 208);
            EXPECT_LE(programs.splat(tables.table(0)).local_memory_bits_used, 208);
        }
    const RegionPrograms programs(format, SplatIndexMode::Affine, SplatBlend::Over, 208);
    for (const PpProgram& p : {programs.point(), programs.sheet_add(), programs.band_composite(), programs.readout()})
        EXPECT_LE(p.local_memory_bits_used, 208) << p.name;
    // With too little local memory the error names the machine's key.
    const RegionPrograms small(format, SplatIndexMode::Exact, SplatBlend::Over, 150);
    try {
        (void)small.splat(tables.table(0));
        FAIL() << "a program that cannot fit was built";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("renderer.local_memory_bits"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pp5
