// load_raw: the caller's layout against the file's bytes.

#include "scene/volume/volume_io.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace pp5 {
namespace {

using namespace pp5::test;
using ::testing::HasSubstr;

const glm::ivec3 kRawDims{5, 7, 3};  // odd on purpose: no axis may be mistaken for another

std::vector<float> values(bool negative) {
    return pattern(kRawDims, [&](int x, int y, int z) {
        const float v = static_cast<float>(x + 5 * y + 35 * z);
        return negative && (x + z) % 2 == 1 ? -v * 100.0f : v;
    });
}

class RawTest : public ::testing::Test {
protected:
    TempDir dir;

    std::filesystem::path write(const std::string& name, const Bytes& bytes) {
        const auto path = dir / name;
        write_file(path, bytes);
        return path;
    }

    InputError error_for(const Bytes& bytes, const RawLayout& layout) {
        const auto path = write("bad.raw", bytes);
        const InputError e = input_error_from([&] { load_raw(path, layout); });
        EXPECT_EQ(e.file(), path.string());
        return e;
    }
};

TEST_F(RawTest, RoundTripsUInt8) {
    const auto expected = values(false);
    const auto path = write("u8.raw", sample_bytes(cast_all<std::uint8_t>(expected)));
    const Volume v = load_raw(path, RawLayout{kRawDims, ScalarType::UInt8, false, 0, glm::vec3(1.0f)});
    EXPECT_EQ(v.dims(), kRawDims);
    EXPECT_EQ(v.source_type(), ScalarType::UInt8);
    EXPECT_EQ(samples_of(v), expected);
    EXPECT_EQ(v.at(4, 6, 2), 4.0f + 30.0f + 70.0f);
    EXPECT_EQ(v.name(), "u8.raw");
}

TEST_F(RawTest, RoundTripsInt16InBothByteOrders) {
    const auto expected = values(true);
    for (const bool big : {false, true}) {
        const auto order = big ? std::endian::big : std::endian::little;
        const auto path = write("i16.raw", sample_bytes(cast_all<std::int16_t>(expected), order));
        const Volume v = load_raw(path, RawLayout{kRawDims, ScalarType::Int16, big, 0, glm::vec3(1.0f)});
        EXPECT_EQ(v.source_type(), ScalarType::Int16);
        EXPECT_EQ(samples_of(v), expected) << (big ? "big-endian" : "little-endian");
    }
}

TEST_F(RawTest, ByteOrderMatters) {
    const auto path = write("i16.raw", sample_bytes(std::vector<std::int16_t>{1, 256}, std::endian::big));
    const Volume v = load_raw(path, RawLayout{{2, 1, 1}, ScalarType::Int16, false, 0, glm::vec3(1.0f)});
    EXPECT_EQ(v.at(0, 0, 0), 256.0f);
    EXPECT_EQ(v.at(1, 0, 0), 1.0f);
}

TEST_F(RawTest, RoundTripsFloat32WithHeaderBytesAndSpacing) {
    const auto expected = pattern(
        kRawDims, [](int x, int y, int z) { return 0.25f * static_cast<float>(x) - 3.5f * static_cast<float>(y * z); });
    for (const bool big : {false, true}) {
        Bytes bytes(17, std::byte{0x5a});
        const Bytes samples = sample_bytes(expected, big ? std::endian::big : std::endian::little);
        bytes.insert(bytes.end(), samples.begin(), samples.end());
        const auto path = write("f32.raw", bytes);
        const Volume v = load_raw(path, RawLayout{kRawDims, ScalarType::Float32, big, 17, {0.5f, 1.0f, 3.0f}});
        EXPECT_EQ(samples_of(v), expected);
        EXPECT_EQ(v.spacing(), glm::vec3(0.5f, 1.0f, 3.0f));
        EXPECT_EQ(v.physical_extent(), glm::vec3(2.5f, 7.0f, 9.0f));
    }
}

TEST_F(RawTest, SamplesThatLookLikeGzipAreNotDecompressed) {
    // 1f 8b is the gzip magic; a raw volume may well start with those two values.
    const std::vector<std::uint8_t> bytes{0x1f, 0x8b, 0x08, 0x00, 0x01, 0x02, 0x03, 0x04};
    const auto path = write("gzlike.raw", sample_bytes(bytes));
    const Volume v = load_raw(path, RawLayout{{2, 2, 2}, ScalarType::UInt8, false, 0, glm::vec3(1.0f)});
    EXPECT_EQ(v.at(0, 0, 0), 31.0f);
    EXPECT_EQ(v.at(1, 0, 0), 139.0f);
    EXPECT_EQ(v.at(1, 1, 1), 4.0f);
}

TEST_F(RawTest, TooShort) {
    const InputError e = error_for(Bytes(1000), RawLayout{{10, 10, 11}, ScalarType::Int16, false, 0, glm::vec3(1.0f)});
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_EQ(e.reason(), "file holds 1000 bytes of voxel data but dims 10x10x11 of int16 need 2200");
}

TEST_F(RawTest, TooLong) {
    const InputError e = error_for(Bytes(106), RawLayout{kRawDims, ScalarType::UInt8, false, 0, glm::vec3(1.0f)});
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_THAT(e.reason(), HasSubstr("holds 106 bytes"));
    EXPECT_THAT(e.reason(), HasSubstr("need 105"));
}

TEST_F(RawTest, HeaderBytesBeyondTheFile) {
    const InputError e = error_for(Bytes(50), RawLayout{kRawDims, ScalarType::UInt8, false, 64, glm::vec3(1.0f)});
    EXPECT_EQ(e.field(), "header_bytes");
}

TEST_F(RawTest, BadDims) {
    EXPECT_EQ(error_for(Bytes(105), RawLayout{{5, 0, 3}, ScalarType::UInt8, false, 0, glm::vec3(1.0f)}).field(),
              "dims.y");
    EXPECT_EQ(error_for(Bytes(105), RawLayout{{5, 7, -3}, ScalarType::UInt8, false, 0, glm::vec3(1.0f)}).field(),
              "dims.z");
    EXPECT_EQ(error_for(Bytes(105), RawLayout{{5000, 7, 3}, ScalarType::UInt8, false, 0, glm::vec3(1.0f)}).field(),
              "dims.x");
}

TEST_F(RawTest, BadSpacing) {
    EXPECT_EQ(error_for(Bytes(105), RawLayout{kRawDims, ScalarType::UInt8, false, 0, {1.0f, 1.0f, 0.0f}}).field(),
              "spacing.z");
    EXPECT_EQ(error_for(Bytes(105), RawLayout{kRawDims, ScalarType::UInt8, false, 0, {-1.0f, 1.0f, 1.0f}}).field(),
              "spacing.x");
    EXPECT_EQ(
        error_for(
            Bytes(105),
            RawLayout{kRawDims, ScalarType::UInt8, false, 0, {1.0f, std::numeric_limits<float>::quiet_NaN(), 1.0f}})
            .field(),
        "spacing.y");
}

TEST_F(RawTest, NaNInFloatData) {
    auto v = pattern(kRawDims, [](int x, int, int) { return static_cast<float>(x); });
    v[2 + 5 * 3 + 35 * 1] = std::numeric_limits<float>::quiet_NaN();  // (2, 3, 1)
    const InputError e =
        error_for(sample_bytes(v), RawLayout{kRawDims, ScalarType::Float32, false, 0, glm::vec3(1.0f)});
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_THAT(e.reason(), HasSubstr("(2, 3, 1) is NaN"));
}

TEST_F(RawTest, MissingFile) {
    const auto path = dir / "nothing.raw";
    const InputError e = input_error_from([&] {
        load_raw(path, RawLayout{kRawDims, ScalarType::UInt8, false, 0, glm::vec3(1.0f)});
    });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "file");
}

}  // namespace
}  // namespace pp5
