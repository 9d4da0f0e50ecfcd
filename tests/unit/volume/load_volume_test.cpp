// load_volume's choice of loader, and the Debian-packaged datasets.

#include "scene/volume/datasets.h"
#include "scene/volume/volume_io.h"
#include "tests/unit/volume/volume_test_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace pp5 {
namespace {

using namespace pp5::test;
using ::testing::HasSubstr;

const glm::ivec3 kSmallDims{3, 2, 2};

Bytes u8_samples() { return sample_bytes(std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}); }

Bytes small_nifti() {
    NiftiSpec spec;
    spec.set_dims(kSmallDims.x, kSmallDims.y, kSmallDims.z);
    return nifti_bytes(spec, u8_samples());
}

TEST(LoadVolume, ChoosesTheLoaderByExtension) {
    TempDir dir;
    write_file(dir / "a.nii", small_nifti());
    write_gz(dir / "b.nii.gz", small_nifti());
    write_file(dir / "C.NII", small_nifti());
    write_file(dir / "d.den", den_bytes(kSmallDims, u8_samples()));
    write_gz(dir / "e.den.gz", den_bytes(kSmallDims, u8_samples()));
    for (const char* name : {"a.nii", "b.nii.gz", "C.NII", "d.den", "e.den.gz"}) {
        const Volume v = load_volume(dir / name);
        EXPECT_EQ(v.dims(), kSmallDims) << name;
        EXPECT_EQ(v.at(2, 1, 1), 12.0f) << name;
    }
}

TEST(LoadVolume, UnknownExtensionNamesTheKnownOnesAndRaw) {
    TempDir dir;
    const auto path = dir / "head.raw";
    write_file(path, u8_samples());
    const InputError e = input_error_from([&] { load_volume(path); });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "file name");
    EXPECT_THAT(e.reason(), HasSubstr(".nii.gz"));
    EXPECT_THAT(e.reason(), HasSubstr(".den"));
    EXPECT_THAT(e.reason(), HasSubstr("raw file needs its dims and"));
}

TEST(LoadVolume, AnalyzePairIsExplained) {
    TempDir dir;
    const auto path = dir / "head.hdr";
    write_file(path, Bytes(348));
    EXPECT_THAT(input_error_from([&] { load_volume(path); }).reason(), HasSubstr(".hdr/.img"));
}

TEST(LoadVolume, MissingFileIsReportedBeforeTheExtension) {
    TempDir dir;
    const auto path = dir / "typo.nii";
    const InputError e = input_error_from([&] { load_volume(path); });
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "file");
}

// A small gzip file whose header declares more than this computer could hold (here 4096^3 voxels, a
// third of a terabyte) is refused before a byte of the samples is inflated, saying what it would need.
TEST(LoadVolume, AHeaderDeclaringMoreThanTheHostHoldsIsRefusedBeforeReading) {
    TempDir dir;
    NiftiSpec spec;
    spec.set_dims(4096, 4096, 4096);
    write_gz(dir / "bomb.nii.gz", nifti_bytes(spec, Bytes(4096)));
    // (A .den header's 32-bit voxel count cannot declare more than about 11 GB.)
    for (const char* name : {"bomb.nii.gz"}) {
        const InputError e = input_error_from([&] { load_volume(dir / name); });
        EXPECT_THAT(e.reason(), HasSubstr("loading a 4096x4096x4096 volume of uint8 needs 343.6 GB"))
            << name << ": " << e.what();
        EXPECT_THAT(e.reason(), HasSubstr("of this computer's memory")) << e.what();
        EXPECT_THAT(e.field(), HasSubstr("header.")) << e.what();
    }
}

TEST(PackagedDatasets, ListsTheDebianVolumes) {
    const auto all = packaged_datasets();
    ASSERT_EQ(all.size(), 4u);
    for (const auto& d : all) {
        EXPECT_FALSE(d.name.empty());
        EXPECT_FALSE(d.package.empty());
        EXPECT_FALSE(d.description.empty());
        EXPECT_TRUE(std::filesystem::path(d.path).is_absolute()) << d.path;
        EXPECT_EQ(find_packaged_dataset(d.name), &d);
    }
    ASSERT_NE(find_packaged_dataset("ch2"), nullptr);
    EXPECT_EQ(find_packaged_dataset("ch2")->package, "mricron-data");
    EXPECT_EQ(find_packaged_dataset("brainsmall")->package, "libvolpack1-dev");
    EXPECT_EQ(find_packaged_dataset("ct-head")->package, "invesalius-examples");
    EXPECT_EQ(find_packaged_dataset("ch3"), nullptr);
}

TEST(PackagedDatasets, UnknownNameListsTheKnownOnes) {
    const InputError e = input_error_from([] { load_packaged_dataset("colin"); });
    EXPECT_EQ(e.field(), "dataset");
    EXPECT_THAT(e.reason(), HasSubstr("ch2, ch2better, brainsmall"));
}

TEST(PackagedDatasets, Ch2IsTheColin27Head) {
    const PackagedDataset* ch2 = find_packaged_dataset("ch2");
    ASSERT_NE(ch2, nullptr);
    if (!std::filesystem::exists(ch2->path)) GTEST_SKIP() << ch2->path << " absent: apt-get install mricron-data";
    const Volume v = load_packaged_dataset("ch2");
    EXPECT_EQ(v.dims(), glm::ivec3(181, 217, 181));
    EXPECT_EQ(v.source_type(), ScalarType::UInt8);
    EXPECT_EQ(v.spacing(), glm::vec3(1.0f));
    EXPECT_EQ(v.name(), "ch2");
    EXPECT_GT(v.max_value(), 100.0f);
}

TEST(PackagedDatasets, BrainsmallLoadsByName) {
    const PackagedDataset* d = find_packaged_dataset("brainsmall");
    ASSERT_NE(d, nullptr);
    if (!std::filesystem::exists(d->path) && !std::filesystem::exists(d->path + ".gz"))
        GTEST_SKIP() << d->path << " absent: apt-get install libvolpack1-dev";
    const Volume v = load_packaged_dataset("brainsmall");
    EXPECT_EQ(v.dims(), glm::ivec3(128, 128, 84));
    EXPECT_EQ(v.name(), "brainsmall");
}

}  // namespace
}  // namespace pp5
