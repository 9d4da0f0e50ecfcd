// load_nifti: round trips through files written here byte by byte, and every refusal.

#include "scene/volume/volume_io.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

namespace pp5 {
namespace {

using namespace pp5::test;
using ::testing::HasSubstr;

const glm::ivec3 kNiftiDims{5, 7, 3};

std::vector<float> small_pattern() {
    return pattern(kNiftiDims, [](int x, int y, int z) { return static_cast<float>(x + 10 * y + 70 * z) * 0.5f; });
}

NiftiSpec spec_for(std::int16_t datatype, std::int16_t bitpix) {
    NiftiSpec s;
    s.set_dims(kNiftiDims.x, kNiftiDims.y, kNiftiDims.z);
    s.datatype = datatype;
    s.bitpix = bitpix;
    return s;
}

NiftiSpec uint8_spec() { return spec_for(2, 8); }

Bytes uint8_samples() { return sample_bytes(cast_all<std::uint8_t>(small_pattern())); }

class NiftiTest : public ::testing::Test {
protected:
    TempDir dir;

    std::filesystem::path write(const std::string& name, const Bytes& bytes) {
        const auto path = dir / name;
        write_file(path, bytes);
        return path;
    }

    InputError error_for(const NiftiSpec& spec, const Bytes& samples, const std::string& name = "bad.nii") {
        const auto path = write(name, nifti_bytes(spec, samples));
        const InputError e = input_error_from([&] { load_nifti(path); });
        EXPECT_EQ(e.file(), path.string());
        return e;
    }
};

TEST_F(NiftiTest, RoundTripsUInt8WithSpacingAndName) {
    NiftiSpec spec = uint8_spec();
    spec.pixdim = {1, 0.5f, 0.75f, 2.0f, 1, 1, 1, 1};
    const auto path = write("small.nii", nifti_bytes(spec, uint8_samples()));
    const Volume v = load_nifti(path);
    EXPECT_EQ(v.dims(), kNiftiDims);
    EXPECT_EQ(v.spacing(), glm::vec3(0.5f, 0.75f, 2.0f));
    EXPECT_EQ(v.source_type(), ScalarType::UInt8);
    EXPECT_EQ(v.name(), "small.nii");
    const auto expected = pattern(kNiftiDims, [](int x, int y, int z) {
        return static_cast<float>(static_cast<std::uint8_t>(static_cast<float>(x + 10 * y + 70 * z) * 0.5f));
    });
    EXPECT_EQ(samples_of(v), expected);
    EXPECT_EQ(v.at(4, 6, 2), expected.back());
}

TEST_F(NiftiTest, RoundTripsGzippedInt16WithNegativeValues) {
    const auto values =
        pattern(kNiftiDims, [](int x, int y, int z) { return static_cast<float>(x * 300 - y * 900 + z * 7); });
    const auto path = dir / "signed.nii.gz";
    write_gz(path, nifti_bytes(spec_for(4, 16), sample_bytes(cast_all<std::int16_t>(values))));
    const Volume v = load_nifti(path);
    EXPECT_EQ(v.source_type(), ScalarType::Int16);
    EXPECT_EQ(samples_of(v), values);
    EXPECT_EQ(v.min_value(), -5400.0f);
}

struct TypeCase {
    std::int16_t code;
    std::int16_t bitpix;
    ScalarType type;
};

std::string type_case_name(const ::testing::TestParamInfo<TypeCase>& c) { return std::string(to_string(c.param.type)); }

class NiftiTypeTest : public NiftiTest, public ::testing::WithParamInterface<TypeCase> {};

template <class T>
Bytes encode_as(const std::vector<float>& values, std::endian order) {
    return sample_bytes(cast_all<T>(values), order);
}

Bytes encode(ScalarType type, const std::vector<float>& values, std::endian order) {
    switch (type) {
        case ScalarType::UInt8: return encode_as<std::uint8_t>(values, order);
        case ScalarType::Int8: return encode_as<std::int8_t>(values, order);
        case ScalarType::UInt16: return encode_as<std::uint16_t>(values, order);
        case ScalarType::Int16: return encode_as<std::int16_t>(values, order);
        case ScalarType::UInt32: return encode_as<std::uint32_t>(values, order);
        case ScalarType::Int32: return encode_as<std::int32_t>(values, order);
        case ScalarType::Float32: return encode_as<float>(values, order);
        case ScalarType::Float64: return encode_as<double>(values, order);
    }
    return {};
}

TEST_P(NiftiTypeTest, RoundTripsEveryDatatypeInBothByteOrders) {
    const TypeCase c = GetParam();
    const bool is_signed = c.type == ScalarType::Int8 || c.type == ScalarType::Int16 || c.type == ScalarType::Int32 ||
                           c.type == ScalarType::Float32 || c.type == ScalarType::Float64;
    const auto values = pattern(kNiftiDims, [&](int x, int y, int z) {
        const float v = static_cast<float>((x * 7 + y * 13 + z * 29) % 120);
        return is_signed && (x + y) % 2 == 1 ? -v : v;
    });
    for (const std::endian order : {std::endian::little, std::endian::big}) {
        NiftiSpec spec = spec_for(c.code, c.bitpix);
        spec.order = order;
        const auto path = write("typed.nii", nifti_bytes(spec, encode(c.type, values, order)));
        const Volume v = load_nifti(path);
        EXPECT_EQ(v.source_type(), c.type) << to_string(c.type);
        EXPECT_EQ(samples_of(v), values) << to_string(c.type) << (order == std::endian::big ? " big" : " little");
    }
}

INSTANTIATE_TEST_SUITE_P(AllTypes, NiftiTypeTest,
                         ::testing::Values(TypeCase{2, 8, ScalarType::UInt8}, TypeCase{256, 8, ScalarType::Int8},
                                           TypeCase{512, 16, ScalarType::UInt16}, TypeCase{4, 16, ScalarType::Int16},
                                           TypeCase{768, 32, ScalarType::UInt32}, TypeCase{8, 32, ScalarType::Int32},
                                           TypeCase{16, 32, ScalarType::Float32},
                                           TypeCase{64, 64, ScalarType::Float64}),
                         type_case_name);

TEST_F(NiftiTest, AppliesSlopeAndInterceptKeepingTheStoredType) {
    NiftiSpec spec = uint8_spec();
    spec.scl_slope = 0.5f;
    spec.scl_inter = -10.0f;
    const auto path = write("scaled.nii", nifti_bytes(spec, uint8_samples()));
    const Volume v = load_nifti(path);
    EXPECT_EQ(v.source_type(), ScalarType::UInt8);
    const auto raw = cast_all<std::uint8_t>(small_pattern());
    for (std::size_t i = 0; i < raw.size(); ++i) EXPECT_FLOAT_EQ(v.samples()[i], 0.5f * raw[i] - 10.0f) << i;
}

TEST_F(NiftiTest, IgnoresIdentityZeroAndNaNSlopes) {
    for (const float slope : {1.0f, 0.0f, std::numeric_limits<float>::quiet_NaN()}) {
        NiftiSpec spec = uint8_spec();
        spec.scl_slope = slope;
        spec.scl_inter = std::isnan(slope) ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
        const auto path = write("unscaled.nii", nifti_bytes(spec, uint8_samples()));
        const auto raw = cast_all<std::uint8_t>(small_pattern());
        EXPECT_EQ(samples_of(load_nifti(path)), std::vector<float>(raw.begin(), raw.end())) << slope;
    }
}

TEST_F(NiftiTest, ZeroPixdimMeansUnitSpacing) {
    NiftiSpec spec = uint8_spec();
    spec.pixdim = {0, 0, 2.5f, 0, 0, 0, 0, 0};
    const Volume v = load_nifti(write("zero.nii", nifti_bytes(spec, uint8_samples())));
    EXPECT_EQ(v.spacing(), glm::vec3(1.0f, 2.5f, 1.0f));
}

TEST_F(NiftiTest, ConvertsMicronsAndMetresToMillimetres) {
    NiftiSpec spec = uint8_spec();
    spec.pixdim = {1, 500, 250, 1000, 1, 1, 1, 1};
    spec.xyzt_units = 3;  // micron
    EXPECT_EQ(load_nifti(write("um.nii", nifti_bytes(spec, uint8_samples()))).spacing(), glm::vec3(0.5f, 0.25f, 1.0f));
    spec.pixdim = {1, 0.001f, 0.002f, 0.001f, 1, 1, 1, 1};
    spec.xyzt_units = 1 | 8;  // metre, with a time unit in the upper bits
    const glm::vec3 s = load_nifti(write("m.nii", nifti_bytes(spec, uint8_samples()))).spacing();
    EXPECT_NEAR(s.x, 1.0f, 1e-5f);
    EXPECT_NEAR(s.y, 2.0f, 1e-5f);
}

TEST_F(NiftiTest, SkipsExtensionsUpToVoxOffset) {
    NiftiSpec spec = uint8_spec();
    spec.vox_offset = 416;
    Bytes bytes = nifti_bytes(spec, uint8_samples());
    for (std::size_t i = 348; i < 416; ++i) bytes[i] = std::byte{0xab};  // junk where extensions live
    EXPECT_EQ(load_nifti(write("ext.nii", bytes)).voxel_count(), 105u);
}

TEST_F(NiftiTest, AcceptsAFourthDimensionOfOne) {
    NiftiSpec spec = uint8_spec();
    spec.dim[0] = 4;
    spec.dim[4] = 1;
    EXPECT_EQ(load_nifti(write("4d.nii", nifti_bytes(spec, uint8_samples()))).dims(), kNiftiDims);
}

TEST_F(NiftiTest, ReadsAnOddSizedVolume) {
    NiftiSpec spec = uint8_spec();
    spec.set_dims(1, 1, 1);
    const Volume v = load_nifti(write("one.nii", nifti_bytes(spec, sample_bytes(std::vector<std::uint8_t>{42}))));
    EXPECT_EQ(v.dims(), glm::ivec3(1));
    EXPECT_EQ(v.at(0, 0, 0), 42.0f);
}

// ---- refusals ----

TEST_F(NiftiTest, MissingFile) {
    const auto path = dir / "absent.nii";
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "file");
    EXPECT_THAT(e.reason(), HasSubstr("does not exist"));
}

TEST_F(NiftiTest, DirectoryInsteadOfFile) {
    const auto path = dir / "folder.nii";
    std::filesystem::create_directory(path);
    EXPECT_EQ(input_error_from([&] { load_nifti(path); }).field(), "file");
}

TEST_F(NiftiTest, EmptyFile) {
    const auto path = write("empty.nii", {});
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.field(), "header");
    EXPECT_THAT(e.reason(), HasSubstr("only 0 bytes"));
}

TEST_F(NiftiTest, TruncatedHeader) {
    Bytes bytes = nifti_bytes(uint8_spec(), {});
    bytes.resize(200);
    const auto path = write("short.nii", bytes);
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "header");
    EXPECT_THAT(e.reason(), HasSubstr("200 bytes"));
    EXPECT_THAT(e.reason(), HasSubstr("348"));
}

TEST_F(NiftiTest, WrongSizeofHdr) {
    NiftiSpec spec = uint8_spec();
    spec.sizeof_hdr = 1234;
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.sizeof_hdr");
    EXPECT_THAT(e.reason(), HasSubstr("1234"));
}

TEST_F(NiftiTest, NiftiTwoIsNamed) {
    NiftiSpec spec = uint8_spec();
    spec.sizeof_hdr = 540;
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.sizeof_hdr");
    EXPECT_THAT(e.reason(), HasSubstr("NIfTI-2"));
}

TEST_F(NiftiTest, WrongMagic) {
    NiftiSpec spec = uint8_spec();
    spec.magic = {'x', 'y', 'z', '\0'};
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.magic");
    EXPECT_THAT(e.reason(), HasSubstr("xyz"));
}

TEST_F(NiftiTest, HeaderOfAPairIsRefused) {
    NiftiSpec spec = uint8_spec();
    spec.magic = {'n', 'i', '1', '\0'};
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.magic");
    EXPECT_THAT(e.reason(), HasSubstr(".hdr/.img"));
}

TEST_F(NiftiTest, TwoDimensionalImage) {
    NiftiSpec spec = uint8_spec();
    spec.dim[0] = 2;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.dim[0]");
}

TEST_F(NiftiTest, TimeSeries) {
    NiftiSpec spec = uint8_spec();
    spec.dim[0] = 4;
    spec.dim[4] = 3;
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.dim[4]");
    EXPECT_THAT(e.reason(), HasSubstr("is 3"));
}

TEST_F(NiftiTest, ZeroDimension) {
    NiftiSpec spec = uint8_spec();
    spec.dim[1] = 0;
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.dim[1]");
    EXPECT_THAT(e.reason(), HasSubstr("is 0"));
}

TEST_F(NiftiTest, NegativeDimension) {
    NiftiSpec spec = uint8_spec();
    spec.dim[3] = -7;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.dim[3]");
}

TEST_F(NiftiTest, AbsurdDimension) {
    NiftiSpec spec = uint8_spec();
    spec.dim[2] = 5000;
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.dim[2]");
    EXPECT_THAT(e.reason(), HasSubstr("4096"));
}

TEST_F(NiftiTest, UnsupportedDatatype) {
    NiftiSpec spec = uint8_spec();
    spec.datatype = 128;  // RGB24
    const InputError e = error_for(spec, uint8_samples());
    EXPECT_EQ(e.field(), "header.datatype");
    EXPECT_THAT(e.reason(), HasSubstr("RGB24"));
    spec.datatype = 999;
    EXPECT_THAT(error_for(spec, uint8_samples()).reason(), HasSubstr("not a NIfTI-1 datatype"));
}

TEST_F(NiftiTest, NegativeOrNaNPixdim) {
    NiftiSpec spec = uint8_spec();
    spec.pixdim[2] = -1.0f;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.pixdim[2]");
    spec.pixdim[2] = 1.0f;
    spec.pixdim[3] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.pixdim[3]");
    // So small or so large that the renderers' products and inverses of it would leave a float.
    spec.pixdim[3] = 1e-30f;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.pixdim[3]");
    spec.pixdim[3] = 3e37f;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.pixdim[3]");
}

TEST_F(NiftiTest, VoxOffsetInsideTheHeaderOrFractional) {
    NiftiSpec spec = uint8_spec();
    spec.vox_offset = 0;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.vox_offset");
    spec.vox_offset = 352.5f;
    EXPECT_EQ(error_for(spec, uint8_samples()).field(), "header.vox_offset");
}

TEST_F(NiftiTest, VoxOffsetBeyondTheEnd) {
    NiftiSpec spec = uint8_spec();
    spec.vox_offset = 4000;
    Bytes header = nifti_bytes(spec, {});
    header.resize(352);
    const auto path = write("far.nii", header);
    EXPECT_EQ(input_error_from([&] { load_nifti(path); }).field(), "header.vox_offset");
}

// Found by fuzz_nifti: an offset too large for any size_t was converted to one (undefined behaviour).
TEST_F(NiftiTest, VoxOffsetPastAnyFile) {
    Bytes bytes = nifti_bytes(uint8_spec(), uint8_samples());
    const float far = 6.5e21f;
    std::memcpy(bytes.data() + 108, &far, sizeof far);  // vox_offset, little-endian like the spec
    const auto path = write("beyond.nii", bytes);
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.field(), "header.vox_offset");
    EXPECT_NE(e.reason().find("past the end of any file"), std::string::npos) << e.reason();
}

TEST_F(NiftiTest, TruncatedVoxelData) {
    NiftiSpec spec = spec_for(4, 16);
    spec.set_dims(10, 10, 11);
    const InputError e = error_for(spec, Bytes(1000));
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_EQ(e.reason(), "file holds 1000 bytes of voxel data but dims 10x10x11 of int16 need 2200");
}

TEST_F(NiftiTest, TruncatedGzipStream) {
    Bytes bytes = nifti_bytes(uint8_spec(), uint8_samples());
    const auto whole = dir / "whole.nii.gz";
    write_gz(whole, bytes);
    std::ifstream in(whole, std::ios::binary);
    std::vector<char> gz((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Cut the compressed stream halfway: the header still inflates, the samples do not all.
    Bytes cut(gz.size() * 3 / 4);
    std::memcpy(cut.data(), gz.data(), cut.size());
    const auto path = write("cut.nii.gz", cut);
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_TRUE(e.field() == "voxel data" || e.field() == "header") << e.what();
    EXPECT_THAT(e.reason(), HasSubstr("cut short"));
}

// Every voxel inflates, but the stream stops where its 8-byte trailer (checksum and length) should be:
// a download cut just short of the end is refused, not read as whole. A wrong checksum is refused too.
TEST_F(NiftiTest, GzipStreamWithoutItsTrailerOrWithAWrongChecksum) {
    const auto whole = dir / "whole.nii.gz";
    write_gz(whole, nifti_bytes(uint8_spec(), uint8_samples()));
    std::ifstream in(whole, std::ios::binary);
    const std::vector<char> gz((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Bytes cut(gz.size() - 8);
    std::memcpy(cut.data(), gz.data(), cut.size());
    const auto path = write("no_trailer.nii.gz", cut);
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_THAT(e.reason(), HasSubstr("without its trailer"));

    Bytes wrong_crc(gz.size());
    std::memcpy(wrong_crc.data(), gz.data(), gz.size());
    wrong_crc[gz.size() - 8] ^= std::byte{0x01};
    const auto crc_path = write("wrong_crc.nii.gz", wrong_crc);
    EXPECT_THAT(input_error_from([&] { load_nifti(crc_path); }).reason(), HasSubstr("gzip data is corrupt"));
    EXPECT_NO_THROW(load_nifti(whole));
}

TEST_F(NiftiTest, CorruptGzipData) {
    Bytes bytes = nifti_bytes(uint8_spec(), uint8_samples());
    const auto whole = dir / "whole.nii.gz";
    write_gz(whole, bytes);
    std::ifstream in(whole, std::ios::binary);
    std::vector<char> gz((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Bytes bad(gz.size());
    std::memcpy(bad.data(), gz.data(), bad.size());
    for (std::size_t i = 12; i < bad.size() - 8; ++i) bad[i] = std::byte{0xff};  // deflate data garbled
    const auto path = write("bad.nii.gz", bad);
    const InputError e = input_error_from([&] { load_nifti(path); });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_THAT(e.reason(), HasSubstr("gzip"));
}

TEST_F(NiftiTest, NaNInFloatData) {
    auto values = small_pattern();
    values[1 + 5 * 2] = std::numeric_limits<float>::quiet_NaN();  // voxel (1, 2, 0)
    const InputError e = error_for(spec_for(16, 32), sample_bytes(values));
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_THAT(e.reason(), HasSubstr("(1, 2, 0)"));
    EXPECT_THAT(e.reason(), HasSubstr("NaN"));
}

TEST_F(NiftiTest, InfinityInDoubleData) {
    auto values = cast_all<double>(small_pattern());
    values.back() = -std::numeric_limits<double>::infinity();
    NiftiSpec spec = spec_for(64, 64);
    spec.order = std::endian::big;
    const InputError e = error_for(spec, sample_bytes(values, std::endian::big));
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_THAT(e.reason(), HasSubstr("(4, 6, 2) is infinite"));
}

TEST_F(NiftiTest, DoubleBeyondFloatRange) {
    auto values = cast_all<double>(small_pattern());
    values[3] = 1e300;
    const InputError e = error_for(spec_for(64, 64), sample_bytes(values));
    EXPECT_EQ(e.field(), "voxel data");
    EXPECT_THAT(e.reason(), HasSubstr("float32 range"));
}

}  // namespace
}  // namespace pp5
