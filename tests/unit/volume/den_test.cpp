// load_den: the UNC density format of VolPack's examples.

#include "scene/volume/volume_io.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace pp5 {
namespace {

using namespace pp5::test;
using ::testing::HasSubstr;

const glm::ivec3 kDenDims{6, 4, 3};

std::vector<float> values() {
    return pattern(kDenDims, [](int x, int y, int z) { return static_cast<float>(x * 3 + y * 20 + z * 80); });
}

class DenTest : public ::testing::Test {
protected:
    TempDir dir;

    std::filesystem::path write(const std::string& name, const Bytes& bytes) {
        const auto path = dir / name;
        write_file(path, bytes);
        return path;
    }

    InputError error_for(const Bytes& bytes) {
        const auto path = write("bad.den", bytes);
        const InputError e = input_error_from([&] { load_den(path); });
        EXPECT_EQ(e.file(), path.string());
        return e;
    }
};

TEST_F(DenTest, RoundTripsInBothByteOrders) {
    const auto expected = values();
    for (const auto order : {std::endian::little, std::endian::big}) {
        const auto path =
            write("small.den", den_bytes(kDenDims, sample_bytes(cast_all<std::uint8_t>(expected)), order));
        const Volume v = load_den(path);
        EXPECT_EQ(v.dims(), kDenDims);
        EXPECT_EQ(v.source_type(), ScalarType::UInt8);
        EXPECT_EQ(v.spacing(), glm::vec3(1.0f));
        EXPECT_EQ(samples_of(v), expected);
        EXPECT_EQ(v.name(), "small.den");
    }
}

TEST_F(DenTest, ReadsGzippedFiles) {
    const auto path = dir / "small.den.gz";
    write_gz(path, den_bytes(kDenDims, sample_bytes(cast_all<std::uint8_t>(values()))));
    EXPECT_EQ(samples_of(load_den(path)), values());
}

TEST_F(DenTest, WrongVersion) {
    const InputError e = error_for(den_bytes(kDenDims, Bytes(72), std::endian::little, 7));
    EXPECT_EQ(e.field(), "header.map_version");
    EXPECT_THAT(e.reason(), HasSubstr("0x0007"));
}

TEST_F(DenTest, TruncatedHeader) {
    Bytes bytes = den_bytes(kDenDims, {});
    bytes.resize(40);
    const InputError e = error_for(bytes);
    EXPECT_EQ(e.field(), "header");
    EXPECT_THAT(e.reason(), HasSubstr("40 bytes"));
}

TEST_F(DenTest, InconsistentMapLength) {
    Bytes bytes = den_bytes(kDenDims, Bytes(72));
    bytes[58] = std::byte{71};  // map_length, little-endian low byte
    const InputError e = error_for(bytes);
    EXPECT_EQ(e.field(), "header.map_length");
    EXPECT_THAT(e.reason(), HasSubstr("6x4x3"));
}

TEST_F(DenTest, ZeroDimension) { EXPECT_EQ(error_for(den_bytes({6, 0, 3}, {})).field(), "header.map_len[1]"); }

TEST_F(DenTest, TruncatedData) {
    const InputError e = error_for(den_bytes(kDenDims, Bytes(50)));
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_EQ(e.reason(), "file holds 50 bytes of voxel data but dims 6x4x3 of uint8 need 72");
}

TEST(DenPackaged, BrainsmallFromVolPack) {
    const std::filesystem::path path = "/usr/share/doc/libvolpack1-dev/examples/brainsmall.den";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " absent: apt-get install libvolpack1-dev";
    const Volume v = load_den(path);
    EXPECT_EQ(v.dims(), glm::ivec3(128, 128, 84));
    EXPECT_EQ(v.source_type(), ScalarType::UInt8);
    EXPECT_GT(v.max_value(), 100.0f);  // a head, not an empty box
    EXPECT_EQ(v.min_value(), 0.0f);
}

}  // namespace
}  // namespace pp5
