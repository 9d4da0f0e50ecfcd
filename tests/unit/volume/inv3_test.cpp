// InVesalius .inv3 projects: a gzipped tar of main.plist and a raw matrix, built here in miniature,
// read back exactly; broken archives and plists are refused with the field at fault.

#include "kernels/volume/datasets.h"
#include "kernels/volume/inv3_io.h"
#include "kernels/volume/volume_io.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <string>

namespace pp5::test {
namespace {

const glm::ivec3 kDims{5, 4, 3};

Bytes text_bytes(const std::string& s) {
    Bytes b(s.size());
    std::memcpy(b.data(), s.data(), s.size());
    return b;
}

// A ustar archive of the members, in order (the names under a directory, as InVesalius writes them).
Bytes tar(const std::vector<std::pair<std::string, Bytes>>& members) {
    Bytes out;
    for (const auto& [name, data] : members) {
        char header[512] = {};
        const std::string path = "tmpdir/" + name;
        std::memcpy(header, path.data(), path.size());
        std::snprintf(header + 100, 8, "%07o", 0644);
        std::snprintf(header + 124, 12, "%011o", static_cast<unsigned>(data.size()));
        header[156] = '0';
        std::memcpy(header + 257, "ustar", 5);
        for (char c : header) out.push_back(static_cast<std::byte>(c));
        out.insert(out.end(), data.begin(), data.end());
        out.resize(out.size() + (512 - data.size() % 512) % 512);
    }
    out.resize(out.size() + 1024);  // the end-of-archive blocks
    return out;
}

std::string plist(const std::string& dtype = "int16", const std::string& shape = "<integer>3</integer><integer>4</integer><integer>5</integer>") {
    return "<?xml version=\"1.0\"?>\n<plist version=\"1.0\">\n<dict>\n"
           "  <key>matrix</key>\n  <dict>\n    <key>dtype</key>\n    <string>" + dtype +
           "</string>\n    <key>filename</key>\n    <string>matrix.dat</string>\n    <key>shape</key>\n    <array>" + shape +
           "</array>\n  </dict>\n  <key>modality</key>\n  <string>CT</string>\n"
           "  <key>spacing</key>\n  <array>\n    <real>0.5</real>\n    <real>0.75</real>\n    <real>2.0</real>\n  </array>\n"
           "</dict>\n</plist>\n";
}

std::vector<float> hu_values() {
    return pattern(kDims, [](int x, int y, int z) { return static_cast<float>(-1000 + x * 7 + y * 50 + z * 400); });
}

Bytes matrix_bytes() {
    std::vector<std::int16_t> v;
    for (float f : hu_values()) v.push_back(static_cast<std::int16_t>(f));
    return sample_bytes(v);
}

class Inv3Test : public ::testing::Test {
protected:
    TempDir dir;

    std::filesystem::path write_project(const std::vector<std::pair<std::string, Bytes>>& members) {
        const auto path = dir / "head.inv3";
        write_gz(path, tar(members));
        return path;
    }
    InputError error_for(const std::vector<std::pair<std::string, Bytes>>& members) {
        const auto path = write_project(members);
        return input_error_from([&] { load_inv3(path); });
    }
};

TEST_F(Inv3Test, ReadsShapeSpacingAndSamples) {
    const auto path = write_project({{"main.plist", text_bytes(plist())}, {"matrix.dat", matrix_bytes()}});
    const Volume v = load_volume(path);  // chosen by the .inv3 name
    EXPECT_EQ(v.dims(), kDims);
    EXPECT_EQ(v.spacing(), glm::vec3(0.5f, 0.75f, 2.0f));
    EXPECT_EQ(v.source_type(), ScalarType::Int16);
    EXPECT_EQ(samples_of(v), hu_values());
    EXPECT_EQ(v.at(4, 0, 0), -1000.0f + 28.0f);  // x runs fastest, as numpy's (z, y, x) order stores it
    EXPECT_EQ(v.at(0, 0, 2), -200.0f);
}

TEST_F(Inv3Test, MissingMembersAreNamed) {
    EXPECT_EQ(error_for({{"matrix.dat", matrix_bytes()}}).field(), "main.plist");
    EXPECT_EQ(error_for({{"main.plist", text_bytes(plist())}}).field(), "matrix.dat");
}

TEST_F(Inv3Test, MatrixOfTheWrongSizeIsRefused) {
    Bytes short_matrix = matrix_bytes();
    short_matrix.resize(short_matrix.size() - 2);
    const InputError e = error_for({{"main.plist", text_bytes(plist())}, {"matrix.dat", short_matrix}});
    EXPECT_EQ(e.field(), "matrix.dat");
    EXPECT_NE(e.reason().find("5x4x3"), std::string::npos) << e.reason();
}

TEST_F(Inv3Test, BadPlistFieldsAreNamed) {
    EXPECT_EQ(error_for({{"main.plist", text_bytes(plist("complex64"))}, {"matrix.dat", matrix_bytes()}}).field(),
              "main.plist: matrix.dtype");
    EXPECT_EQ(error_for({{"main.plist", text_bytes(plist("int16", "<integer>3</integer>"))}, {"matrix.dat", matrix_bytes()}}).field(),
              "main.plist: matrix.shape");
    EXPECT_EQ(error_for({{"main.plist", text_bytes("<plist><dict></dict></plist>")}, {"matrix.dat", matrix_bytes()}}).field(),
              "main.plist: matrix");
}

TEST_F(Inv3Test, TruncatedArchiveIsRefused) {
    Bytes archive = tar({{"main.plist", text_bytes(plist())}, {"matrix.dat", matrix_bytes()}});
    archive.resize(700);  // inside matrix.dat
    const auto path = dir / "cut.inv3";
    write_gz(path, archive);
    EXPECT_EQ(input_error_from([&] { load_inv3(path); }).field(), "archive");
}

TEST(Inv3Packaged, CtHeadFromInvesaliusExamples) {
    const PackagedDataset* d = find_packaged_dataset("ct-head");
    ASSERT_NE(d, nullptr);
    if (!std::filesystem::exists(d->path)) GTEST_SKIP() << "invesalius-examples is not installed";
    const Volume v = load_packaged_dataset("ct-head");
    EXPECT_EQ(v.dims(), glm::ivec3(256, 256, 108));
    EXPECT_EQ(v.source_type(), ScalarType::Int16);
    EXPECT_EQ(v.min_value(), -1024.0f);
    EXPECT_GT(v.max_value(), 2000.0f);
    EXPECT_NEAR(v.spacing().z, 1.5f, 1e-6f);
}

}  // namespace
}  // namespace pp5::test
