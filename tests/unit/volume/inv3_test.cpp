// InVesalius .inv3 projects: a gzipped tar of main.plist and a raw matrix, built here in miniature
// from the tar (POSIX ustar) and plist definitions, read back exactly; broken archives, plists and
// matrices are refused with the field at fault. The real CT head is checked when it is installed.

#include "scene/volume/datasets.h"
#include "scene/volume/inv3_io.h"
#include "scene/volume/volume_io.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pp5::test {
namespace {

const glm::ivec3 kInv3Dims{5, 4, 3};  // x, y, z: shape (3, 4, 5) in the plist

std::vector<float> hu_values() {
    return pattern(kInv3Dims, [](int x, int y, int z) { return static_cast<float>(-1000 + x * 7 + y * 50 + z * 400); });
}

Bytes matrix_bytes() { return sample_bytes(cast_all<std::int16_t>(hu_values())); }

Members project(const PlistSpec& spec = {}) {
    return {{"main.plist", text_bytes(plist(spec))}, {"matrix.dat", matrix_bytes()}};
}

Bytes read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> chars{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    Bytes out(chars.size());
    std::memcpy(out.data(), chars.data(), chars.size());
    return out;
}

class Inv3Test : public ::testing::Test {
protected:
    TempDir dir;

    std::filesystem::path write_archive(const Bytes& archive) {
        const auto path = dir / "head.inv3";
        write_gz(path, archive);
        return path;
    }
    InputError error_for_archive(const Bytes& archive) {
        const auto path = write_archive(archive);
        return input_error_from([&] { load_inv3(path); });
    }
    InputError error_for(const Members& members) { return error_for_archive(tar(members)); }
};

TEST_F(Inv3Test, ReadsShapeSpacingAndSamples) {
    const auto path = write_archive(tar(project()));
    const Volume v = load_volume(path);  // chosen by the .inv3 name
    EXPECT_EQ(v.dims(), kInv3Dims);
    EXPECT_EQ(v.spacing(), glm::vec3(0.5f, 0.75f, 2.0f));  // (x, y, z), unlike the shape
    EXPECT_EQ(v.source_type(), ScalarType::Int16);
    EXPECT_EQ(samples_of(v), hu_values());
    EXPECT_EQ(v.name(), "head");
}

// The matrix is numpy's C-order (z, y, x): x fastest, and the first stored slice is z = 0, not flipped.
TEST_F(Inv3Test, StoredOrderIsXFastestAndFirstSliceIsZ0) {
    const Volume v = load_inv3(write_archive(tar(project())));
    EXPECT_EQ(v.at(0, 0, 0), -1000.0f);
    EXPECT_EQ(v.at(4, 0, 0), -1000.0f + 4 * 7);
    EXPECT_EQ(v.at(0, 3, 0), -1000.0f + 3 * 50);
    EXPECT_EQ(v.at(0, 0, 2), -1000.0f + 2 * 400);
}

TEST_F(Inv3Test, MembersInAnyOrderAndTheMatrixByItsPlistName) {
    PlistSpec spec;
    spec.filename = "image.dat";
    const Bytes decoy(7, std::byte{1});
    const Members members{{"mask_0.dat", decoy},
                          {"matrix.dat", decoy},
                          {"image.dat", matrix_bytes()},
                          {"mask_0.plist", text_bytes("<plist/>")},
                          {"main.plist", text_bytes(plist(spec))}};
    const Volume v = load_inv3(write_archive(tar(members)));
    EXPECT_EQ(samples_of(v), hu_values());
}

TEST_F(Inv3Test, OtherDtypesAreReadAsStored) {
    PlistSpec spec;
    spec.dtype = "float32";
    const Volume v = load_inv3(write_archive(
        tar({{"main.plist", text_bytes(plist(spec))}, {"matrix.dat", sample_bytes(cast_all<float>(hu_values()))}})));
    EXPECT_EQ(v.source_type(), ScalarType::Float32);
    EXPECT_EQ(samples_of(v), hu_values());
}

TEST_F(Inv3Test, MissingMembersAreNamed) {
    EXPECT_EQ(error_for({{"matrix.dat", matrix_bytes()}}).field(), "main.plist");
    EXPECT_EQ(error_for({{"main.plist", text_bytes(plist())}}).field(), "matrix.dat");
}

TEST_F(Inv3Test, MissingKeysAreNamed) {
    const auto field_without = [&](void (*drop)(PlistSpec&)) {
        PlistSpec spec;
        drop(spec);
        return error_for(project(spec)).field();
    };
    EXPECT_EQ(field_without([](PlistSpec& s) { s.matrix_dict = false; }), "main.plist: matrix");
    EXPECT_EQ(field_without([](PlistSpec& s) { s.dtype.reset(); }), "main.plist: matrix.dtype");
    EXPECT_EQ(field_without([](PlistSpec& s) { s.filename.reset(); }), "main.plist: matrix.filename");
    EXPECT_EQ(field_without([](PlistSpec& s) { s.shape.reset(); }), "main.plist: matrix.shape");
    EXPECT_EQ(field_without([](PlistSpec& s) { s.spacing.reset(); }), "main.plist: spacing");
}

TEST_F(Inv3Test, MalformedShapeAndSpacingAreNamed) {
    const auto field_with = [&](std::optional<std::string> shape, std::optional<std::string> spacing) {
        PlistSpec spec;
        if (shape) spec.shape = *shape;
        if (spacing) spec.spacing = *spacing;
        return error_for(project(spec)).field();
    };
    EXPECT_EQ(field_with("<integer>3</integer><integer>4</integer>", {}), "main.plist: matrix.shape");
    EXPECT_EQ(field_with("<integer>3</integer><integer>4</integer><real>5.5</real>", {}),
              "main.plist: matrix.shape[2]");
    EXPECT_EQ(field_with("<integer>3x</integer><integer>4</integer><integer>5</integer>", {}),
              "main.plist: matrix.shape[0]");
    EXPECT_EQ(field_with("<integer>3</integer><integer>0</integer><integer>5</integer>", {}),
              "main.plist: matrix.shape[1]");
    EXPECT_EQ(field_with({}, "<real>1</real><real>-1</real><real>1</real>"), "main.plist: spacing[1]");
    EXPECT_EQ(field_with({}, "<real>1</real><real>1</real><string>1</string>"), "main.plist: spacing[2]");
    EXPECT_EQ(field_with({}, "<real>1</real><real>1</real>"), "main.plist: spacing");
}

TEST_F(Inv3Test, UnsupportedDtypeIsRefused) {
    PlistSpec spec;
    spec.dtype = "complex64";
    const InputError e = error_for(project(spec));
    EXPECT_EQ(e.field(), "main.plist: matrix.dtype");
    EXPECT_NE(e.reason().find("complex64"), std::string::npos) << e.reason();
}

TEST_F(Inv3Test, MatrixOfTheWrongSizeIsRefused) {
    Bytes short_matrix = matrix_bytes();
    short_matrix.resize(short_matrix.size() - 2);
    const InputError e = error_for({{"main.plist", text_bytes(plist())}, {"matrix.dat", short_matrix}});
    EXPECT_EQ(e.field(), "matrix.dat");
    EXPECT_NE(e.reason().find("5x4x3"), std::string::npos) << e.reason();
}

// numpy.save's format, should a project ever hold one: the size is off by the header, and the
// message says why.
TEST_F(Inv3Test, NpyMatrixIsExplained) {
    Bytes npy = text_bytes(std::string("\x93NUMPY\x01\x00", 8));
    npy.resize(128, std::byte{' '});
    const Bytes samples = matrix_bytes();
    npy.insert(npy.end(), samples.begin(), samples.end());
    const InputError e = error_for({{"main.plist", text_bytes(plist())}, {"matrix.dat", npy}});
    EXPECT_EQ(e.field(), "matrix.dat");
    EXPECT_NE(e.reason().find(".npy"), std::string::npos) << e.reason();
}

// Cut in the plist's data, in the matrix's header and in the matrix's data: each is a short archive.
TEST_F(Inv3Test, TruncatedArchiveIsRefused) {
    const Bytes archive = tar(project());
    const std::size_t matrix_header = kBlock + padded(plist().size());
    for (const std::size_t cut : {kBlock + 10, matrix_header + 100, matrix_header + kBlock + 20}) {
        const Bytes cut_archive(archive.begin(), archive.begin() + static_cast<std::ptrdiff_t>(cut));
        const InputError e = error_for_archive(cut_archive);
        EXPECT_EQ(e.field(), "archive") << "cut at " << cut;
    }
}

// A gzip stream cut short, as a broken download leaves it. The matrix is noise, so that it compresses
// little and half the file cannot hold it.
TEST_F(Inv3Test, TruncatedGzipIsRefused) {
    const glm::ivec3 dims{32, 32, 8};
    std::uint32_t state = 12345;
    std::vector<std::int16_t> noise;
    for (std::size_t i = 0; i < 32 * 32 * 8; ++i) {
        state = state * 1664525u + 1013904223u;
        noise.push_back(static_cast<std::int16_t>(state >> 16));
    }
    PlistSpec spec;
    spec.shape = "<integer>8</integer><integer>32</integer><integer>32</integer>";
    const auto path =
        write_archive(tar({{"main.plist", text_bytes(plist(spec))}, {"matrix.dat", sample_bytes(noise)}}));
    ASSERT_EQ(load_inv3(path).dims(), dims);  // whole, it loads

    Bytes gz = read_all(path);
    gz.resize(gz.size() / 2);
    write_file(path, gz);
    EXPECT_EQ(input_error_from([&] { load_inv3(path); }).field(), "archive");
}

TEST_F(Inv3Test, BadTarHeaderIsRefused) {
    Bytes archive = tar(project());
    const std::size_t matrix_header = kBlock + padded(plist().size());

    Bytes bad_checksum = archive;
    bad_checksum[matrix_header + 3] ^= std::byte{0x20};  // a letter of the name, checksum left stale
    InputError e = error_for_archive(bad_checksum);
    EXPECT_EQ(e.field(), "archive");
    EXPECT_NE(e.reason().find("checksum"), std::string::npos) << e.reason();

    Bytes bad_size = archive;
    std::memcpy(bad_size.data() + matrix_header + 124, "0000000x170", 11);
    set_checksum(bad_size, matrix_header);
    e = error_for_archive(bad_size);
    EXPECT_EQ(e.field(), "archive");
    EXPECT_NE(e.reason().find("size"), std::string::npos) << e.reason();
}

TEST_F(Inv3Test, FileThatIsNoArchiveIsRefused) {
    const auto path = dir / "notes.inv3";
    write_file(path, text_bytes(std::string(2000, 'x')));
    const InputError e = input_error_from([&] { load_volume(path); });
    EXPECT_EQ(e.field(), "archive");
    EXPECT_NE(e.reason().find("not a gzipped tar"), std::string::npos) << e.reason();

    write_file(path, text_bytes("hello"));  // shorter than one tar header
    EXPECT_EQ(input_error_from([&] { load_volume(path); }).field(), "archive");
}

// The real CT head of invesalius-examples: 108 axial slices of 256x256 int16 Hounsfield units.
TEST(Inv3Packaged, CtHeadFromInvesaliusExamples) {
    const PackagedDataset* d = find_packaged_dataset("ct-head");
    ASSERT_NE(d, nullptr);
    if (!std::filesystem::exists(d->path)) GTEST_SKIP() << "invesalius-examples is not installed";
    const Volume v = load_packaged_dataset("ct-head");
    EXPECT_EQ(v.dims(), glm::ivec3(256, 256, 108));
    EXPECT_EQ(v.source_type(), ScalarType::Int16);
    EXPECT_NEAR(v.spacing().x, 0.957f, 1e-3f);
    EXPECT_NEAR(v.spacing().y, 0.957f, 1e-3f);
    EXPECT_NEAR(v.spacing().z, 1.5f, 1e-6f);
    EXPECT_EQ(v.min_value(), -1024.0f);  // air
    EXPECT_GT(v.max_value(), 2900.0f);   // dense bone and teeth: 2986
    EXPECT_LT(v.max_value(), 3100.0f);

    // Superior is +z: the crown's slice cuts far less of the head than one through the middle.
    const auto head_voxels = [&](int z) {
        int count = 0;
        for (int y = 0; y < v.dims().y; ++y) {
            for (int x = 0; x < v.dims().x; ++x) count += v.at(x, y, z) > -300.0f ? 1 : 0;
        }
        return count;
    };
    EXPECT_LT(head_voxels(v.dims().z - 2) * 4, head_voxels(v.dims().z / 2));
}

}  // namespace
}  // namespace pp5::test
