// PERM's structure: the memory of eqs. (3) and (6) against every cell of the paper's Tables 1 and 2 and
// its 100^3 example, the mapping tables against Figure 3 (and eq. (4)'s carry, the paper's error), and
// the records against the volume they were built from.

#include "kernels/perm/perm_structure.h"
#include "kernels/registry/registry.h"
#include "scene/volume/phantoms.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace pp5 {
namespace {

PermMemory paper(glm::ivec3 dims, std::uint64_t candidates, int d, int g) {
    return PermMemory{dims, candidates, d, g, 2, 1};
}

TEST(PermMemoryEquations, TablesOneAndTwoToTheMegabyte) {
    struct Row {
        const char* dataset;
        glm::ivec3 dims;
        std::uint64_t candidates;
        double table1, table2;  // MB as printed (N_qc = 5; D = 5, G = 3)
    };
    const Row rows[] = {{"teapot", {256, 256, 178}, 601'190, 399, 163},
                        {"bonsai", {256, 256, 256}, 754'117, 505, 209},
                        {"aneurism", {256, 256, 256}, 214'521, 168, 84},
                        {"tooth", {256, 256, 161}, 304'322, 211, 92}};
    for (const Row& r : rows) {
        EXPECT_EQ(std::lround(static_cast<double>(paper(r.dims, r.candidates, 5, 5).total_bytes()) / 1e6),
                  std::lround(r.table1))
            << r.dataset;
        EXPECT_EQ(std::lround(static_cast<double>(paper(r.dims, r.candidates, 5, 3).total_bytes()) / 1e6),
                  std::lround(r.table2))
            << r.dataset;
    }
    // With a plain 4-byte index volume no cell matches: the tables used section 4.3's 2-byte one.
    PermMemory four = paper(rows[0].dims, rows[0].candidates, 5, 5);
    four.index_bytes = 4;
    EXPECT_GT(static_cast<double>(four.total_bytes()) / 1e6, 399 + 20);
    // The per-cell records: 625 bytes at N_qc = 5, 233 at 5/3 (125 + 27 x 4).
    EXPECT_EQ(paper({1, 1, 1}, 1, 5, 5).record_bytes(), 625u);
    EXPECT_EQ(paper({1, 1, 1}, 1, 5, 3).record_bytes(), 233u);
    // The kernel's formula (target files' formula rows) is the same arithmetic.
    const Kernel* perm = find_kernel("perm");
    ASSERT_NE(perm, nullptr);
    const double bonsai = perm->formula("memory_megabytes", {{"dims", {256, 256, 256}},
                                                             {"candidates", {754117}},
                                                             {"density_positions", {5}},
                                                             {"gradient_positions", {3}},
                                                             {"index_bytes", {2}},
                                                             {"density_bytes", {1}}});
    EXPECT_NEAR(bonsai, static_cast<double>(paper({256, 256, 256}, 754'117, 5, 3).total_bytes()) / 1e6, 1e-9);
}

TEST(PermMemoryEquations, TheSummedTableHalvesTheIndexVolume) {
    // Section 4.3: 100^3 with 4-byte indices is 4 MB; with 2-byte indices and the table, 2 MB + 400 B.
    PermMemory plain{{100, 100, 100}, 0, 5, 5, 4, 1};
    PermMemory summed{{100, 100, 100}, 0, 5, 5, 2, 1};
    EXPECT_EQ(plain.total_bytes(), 4'000'000u);
    EXPECT_EQ(summed.index_volume_bytes(), 2'000'000u);
    EXPECT_EQ(summed.summed_table_bytes(), 400u);
}

TEST(PermMappingTable, FigureThreeAndTheCarry) {
    // QBM = 1000, N_qc = 5, eq. (4): t = 200.
    const PositionTable paper_rule(5, 1000, QuantizedPositions::Paper);
    for (int qi = 101; qi <= 299; ++qi) ASSERT_EQ(paper_rule.at(qi), 1) << qi;
    for (int qi = 301; qi <= 499; ++qi) ASSERT_EQ(paper_rule.at(qi), 2) << qi;
    for (int qi = 501; qi <= 699; ++qi) ASSERT_EQ(paper_rule.at(qi), 3) << qi;
    for (int qi = 0; qi < 100; ++qi) ASSERT_EQ(paper_rule.at(qi), 0) << qi;
    // Figure 3 puts qi = 100 (and 300, 500, 700) with the lower position; eq. (4) rounds them up.
    EXPECT_EQ(paper_rule.at(100), 1);
    // Past 900 eq. (4) gives 5, a sixth position that carries into the next axis's digit.
    EXPECT_EQ(paper_rule.at(950), 5);
    const PositionTable rounded(5, 1000, QuantizedPositions::Rounded);
    EXPECT_EQ(rounded.at(950), 4);
    // The worked example (0.48, 0.0, 0.25): digits (2, 0, 1), 2 + 5 x 0 + 25 x 1 = 27 (the paper's
    // "3 + 5 x (0 + 1 x 5)" is 28, a slip; its answer 27 is right).
    EXPECT_EQ(paper_rule.index(0.48f) + 5 * paper_rule.index(0.0f) + 25 * paper_rule.index(0.25f), 27);
    // Centres: the sub-cube a fraction falls in.
    const PositionTable centers(5, 1000, QuantizedPositions::Centers);
    EXPECT_EQ(centers.index(0.0f), 0);
    EXPECT_EQ(centers.index(0.199f), 0);
    EXPECT_EQ(centers.index(0.2f), 1);
    EXPECT_EQ(centers.index(0.999f), 4);
    EXPECT_DOUBLE_EQ(centers.offset(2), 0.5);
}

TEST(PermRecords, HoldTheVolumeAtTheirQuantizedPositions) {
    const Volume v = make_head_phantom(32);
    Classification c;
    c.kind = ClassificationKind::IsovalueContours;
    c.contours = {{60.0f, 0.5f, 1.5f}};
    PermSettings s;
    const PermStructure perm = PermStructure::build(v, c, s);
    ASSERT_GT(perm.candidates(), 100u);
    const float range = v.max_value() - v.min_value();
    for (std::uint32_t k = 0; k < perm.candidates(); k += 37) {
        const glm::ivec3 o = perm.cell_origin(k);
        ASSERT_EQ(perm.index(o.x, o.y, o.z), static_cast<std::int32_t>(k));
        // The sub-cube centred at (0.5, 0.5, 0.5) holds the mean of the eight corners.
        const PermStructure::Sample s0 = perm.lookup(k, glm::vec3(0.5f));
        float mean = 0;
        for (int i = 0; i < 8; ++i) mean += v.at(o.x + (i & 1), o.y + ((i >> 1) & 1), o.z + (i >> 2)) / 8;
        ASSERT_NEAR(s0.value, mean, range / 255.0f);
    }
    // Every candidate's cell may be non-transparent, and more cells are candidates by their corners than by
    // their origin alone.
    PermSettings origin = s;
    origin.candidates = CandidateRule::PaperOrigin;
    EXPECT_LT(PermStructure::build(v, c, origin).candidates(), perm.candidates());
}

TEST(PermRecords, TheSameAtOneAndTwoThreads) {
    const Volume v = make_head_phantom(32);
    Classification c;
    c.kind = ClassificationKind::IsovalueContours;
    c.contours = {{60.0f, 0.5f, 1.5f}};
    const auto build = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        return PermStructure::build(v, c, PermSettings{});
    };
    const PermStructure a = build(1), b = build(2);
    ASSERT_EQ(a.candidates(), b.candidates());
    for (std::uint32_t k = 0; k < a.candidates(); ++k) {
        ASSERT_EQ(a.cell_origin(k), b.cell_origin(k));
        const auto sa = a.lookup(k, glm::vec3(0.3f, 0.7f, 0.1f)), sb = b.lookup(k, glm::vec3(0.3f, 0.7f, 0.1f));
        ASSERT_EQ(sa.value, sb.value);
        ASSERT_EQ(sa.gradient, sb.gradient);
    }
}

}  // namespace
}  // namespace pp5
