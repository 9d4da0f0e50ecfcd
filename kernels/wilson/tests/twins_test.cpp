// Each of Wilson's region programs against its functional twin: random slices (parallel and
// perspective) of random quads, slice composites, points and GP-composited blocks, drawn one after
// another into the same region, must leave every PP's fields bit for bit as the twins leave them,
// including the PPs outside each primitive's box (which the twins never visit).

#include "kernels/wilson/slice_geometry.h"
#include "kernels/wilson/slice_programs.h"

#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <random>

namespace pp5 {
namespace {

constexpr int kSize = 48;  // a small region: 48 x 48 PPs
constexpr int kMemory = 208;

void expect_same_state(const PpArray& array, const PpProgram& program, const SliceRegion& twin,
                       const std::string& after) {
    // The region state is the first nine fields of every program: C (3), A, S (4), K.
    for (int f = 0; f < 9; ++f) {
        const auto values = array.field_values(program.fields[static_cast<std::size_t>(f)]);
        const std::vector<std::int32_t>& expected = f < 3    ? twin.color[f]
                                                    : f == 3 ? twin.alpha
                                                    : f < 8  ? twin.slice[f - 4]
                                                             : twin.key;
        int differing = 0;
        for (std::size_t p = 0; p < expected.size(); ++p) differing += values[p] != expected[p] ? 1 : 0;
        ASSERT_EQ(differing, 0) << program.field_names[static_cast<std::size_t>(f)] << " after " << after;
    }
}

Camera camera(bool perspective) {
    Camera c;
    c.projection = perspective ? Projection::Perspective : Projection::Parallel;
    c.eye = {-30, -50, -160};
    c.target = {20, 20, 20};
    c.up = {0, 1, 0};
    c.fov_y_degrees = 30.0f;
    c.view_height = 60.0f;
    return c;
}

// Writes `block`'s pixels into the slice buffer as the controller does before a block-over run.
PpProgram stage_block(const SliceFormat& f, int x0, int y0, int x1, int y1,
                      const std::vector<std::array<std::int32_t, 4>>& block) {
    // A table indexed by the pixel's number carries each PP's staged value (a test's stand-in for the
    // controller's writes).
    PpProgramBuilder b("stage block", kMemory);
    PpField state[9];
    const char* names[9] = {"C_red", "C_green", "C_blue", "A", "S_red", "S_green", "S_blue", "S_opacity", "K"};
    for (int i = 0; i < 9; ++i)
        state[i] = b.alloc(names[i], i == 8 ? SliceFormat::kKeyBits : f.accumulator_bits, false);
    b.enable_all();
    const PpField pixel = b.qee("pixel", 0, 12, false, 0);
    for (int c = 0; c < 4; ++c) {
        PpTable table{"staged", std::vector<std::int64_t>(4096, 0)};
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x)
                table.entries[static_cast<std::size_t>(y * kSize + x)] =
                    block[static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(x1 - x0 + 1) +
                          static_cast<std::size_t>(x - x0)][static_cast<std::size_t>(c)];
        const PpField v = b.lookup("v", pixel, table, f.accumulator_bits, false);
        b.assign(state[4 + c], v);
        b.release(v);
    }
    return b.finish();
}

class SliceTwins : public ::testing::TestWithParam<bool> {};

TEST_P(SliceTwins, TwinsMatchTheProgramsOnAPpArray) {
    const bool perspective = GetParam();
    const SliceFormat format{12};
    const SlicePrograms programs(format, kMemory);
    const ScreenProjection projection(camera(perspective), 160, 160);
    const int ox = 56, oy = 40;  // the region's origin on the screen
    PpArray array(kSize, kSize, kMemory, 64);
    SliceRegion twin(kSize, kSize);
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const glm::vec3 spacing(1.0f, 1.0f, 1.2f);
    int quads = 0, points = 0, blocks = 0;
    for (int layer = 0; layer < 6; ++layer) {
        // A slice: setup, its quads (texel cells near the region), composite.
        const SlicePlane plane(projection, layer % 3, 8 + 3 * layer, spacing, 2);
        const SliceSetup setup = plane.setup(ox, oy);
        const PpProgram setup_program = programs.setup(perspective);
        array.run(setup_program, PpSlotContext{0, setup.expressions});
        setup_slice(twin, setup);
        expect_same_state(array, setup_program, twin, "setup " + std::to_string(layer));
        const PpProgram quad_program = programs.quad();
        for (int j = 0; j < 30; ++j)
            for (int i = 0; i < 30; ++i) {
                // The cell's pixels: where the key says so (any in the region).
                const std::int64_t key = SliceFormat::key(i + 1, j + 1);
                int x0 = kSize, y0 = kSize, x1 = -1, y1 = -1;
                for (int y = 0; y < kSize; ++y)
                    for (int x = 0; x < kSize; ++x)
                        if (twin.key[twin.index(x, y)] == key) {
                            x0 = std::min(x0, x);
                            y0 = std::min(y0, y);
                            x1 = std::max(x1, x);
                            y1 = std::max(y1, y);
                        }
                if (x1 < 0 || unit(random) < 0.3) continue;
                std::array<std::array<double, 2>, 2> f[4];
                for (auto& channel : f)
                    for (auto& row : channel)
                        for (double& v : row) v = unit(random);
                QuadDraw draw;
                draw.key = key;
                const glm::dvec2 centre =
                    projection.to_screen(projection.to_eye(glm::vec3(plane.world(i + 0.5, j + 0.5))));
                for (int c = 0; c < 4; ++c) {
                    const Quadratic q = cell_quadratic(plane, i, j, f[c], centre).shifted(ox, oy);
                    draw.channels[static_cast<std::size_t>(c)] =
                        to_qee(q.a, q.b, q.c, q.d, q.e, q.f, static_cast<double>(format.one()));
                }
                draw.x0 = x0;
                draw.y0 = y0;
                draw.x1 = x1;
                draw.y1 = y1;
                array.run(quad_program, PpSlotContext{0, SlicePrograms::expressions(draw)});
                draw_quad(twin, draw, format);
                ++quads;
            }
        expect_same_state(array, quad_program, twin, "quads of slice " + std::to_string(layer));
        const PpProgram composite = programs.composite();
        array.run(composite, PpSlotContext{0, {}});
        composite_slice(twin, format);
        expect_same_state(array, composite, twin, "composite " + std::to_string(layer));
        // A slab: points as primitives, then a GP-composited block.
        const PpProgram point_program = programs.point();
        std::vector<PointSquare> slab;
        for (int k = 0; k < 12; ++k) {
            PointSquare p;
            const int side = 1 + static_cast<int>(unit(random) * 4);
            p.x0 = static_cast<int>(unit(random) * (kSize + 8)) - 4;
            p.y0 = static_cast<int>(unit(random) * (kSize + 8)) - 4;
            p.x1 = p.x0 + side - 1;
            p.y1 = p.y0 + side - 1;
            const double a = unit(random);
            p.premultiplied[3] = std::llround(a * static_cast<double>(format.top()));
            for (int c = 0; c < 3; ++c)
                p.premultiplied[static_cast<std::size_t>(c)] =
                    std::llround(a * unit(random) * static_cast<double>(format.top()));
            slab.push_back(p);
            array.run(point_program, PpSlotContext{0, SlicePrograms::expressions(p)});
            draw_point_square(twin, p, format);
            ++points;
        }
        expect_same_state(array, point_program, twin, "points of slab " + std::to_string(layer));
        const int bx0 = 3 + layer, by0 = 5, bx1 = 30 + layer, by1 = 40;
        std::vector<std::array<std::int32_t, 4>> block(
            static_cast<std::size_t>(bx1 - bx0 + 1) * static_cast<std::size_t>(by1 - by0 + 1), {0, 0, 0, 0});
        for (const PointSquare& p : slab) composite_point_into(block, bx0, by0, bx1, by1, p, format);
        const PpProgram stage = stage_block(format, bx0, by0, bx1, by1, block);
        const std::vector<QeeCoefficients> pixel_number = {QeeCoefficients{0, 0, 0, 1, kSize, 0}};
        array.run(stage, PpSlotContext{0, pixel_number});
        const PpProgram over = programs.block_over();
        array.run(over, PpSlotContext{0, {}});
        draw_block_over(twin, bx0, by0, bx1, by1, block, format);
        expect_same_state(array, over, twin, "block of slab " + std::to_string(layer));
        ++blocks;
    }
    EXPECT_GT(quads, 100);
    EXPECT_GT(points, 50);
    EXPECT_EQ(blocks, 6);
}

INSTANTIATE_TEST_SUITE_P(Cameras, SliceTwins, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& param_info) {
                             return param_info.param ? "perspective" : "parallel";
                         });

TEST(SlicePrograms, FitTheRenderersLocalMemory) {
    const SlicePrograms programs(SliceFormat{12}, 208);
    for (const PpProgram& p : {programs.setup(false), programs.setup(true), programs.quad(), programs.composite(),
                               programs.point(), programs.block_over(), programs.readout()})
        EXPECT_LE(p.local_memory_bits_used, 208) << p.name;
    const SlicePrograms small(SliceFormat{12}, 160);
    try {
        (void)small.setup(true);
        FAIL() << "a program that cannot fit was built";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("renderer.local_memory_bits"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pp5
