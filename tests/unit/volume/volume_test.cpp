// The Volume type and scalar type helpers.

#include "scene/volume/volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace pp5 {
namespace {

TEST(ScalarType, NamesSizesAndParsingAgree) {
    const ScalarType all[] = {ScalarType::UInt8,  ScalarType::Int8,  ScalarType::UInt16,  ScalarType::Int16,
                              ScalarType::UInt32, ScalarType::Int32, ScalarType::Float32, ScalarType::Float64};
    const std::size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    for (std::size_t i = 0; i < std::size(all); ++i) {
        EXPECT_EQ(parse_scalar_type(to_string(all[i])), all[i]) << to_string(all[i]);
        EXPECT_EQ(scalar_size_bytes(all[i]), sizes[i]) << to_string(all[i]);
    }
    EXPECT_EQ(to_string(ScalarType::Int16), "int16");
    EXPECT_EQ(parse_scalar_type("float"), ScalarType::Float32);
    EXPECT_EQ(parse_scalar_type("double"), ScalarType::Float64);
    EXPECT_FALSE(parse_scalar_type("int64"));
    EXPECT_FALSE(parse_scalar_type(""));
}

TEST(Volume, KeepsMetadataAndComputesRange) {
    std::vector<float> samples{3, -2, 7, 0, 1, 1};
    const Volume v({3, 2, 1}, {0.5f, 2.0f, 1.5f}, ScalarType::Int16, samples, "tiny");
    EXPECT_EQ(v.dims(), glm::ivec3(3, 2, 1));
    EXPECT_EQ(v.spacing(), glm::vec3(0.5f, 2.0f, 1.5f));
    EXPECT_EQ(v.physical_extent(), glm::vec3(1.5f, 4.0f, 1.5f));
    EXPECT_EQ(v.source_type(), ScalarType::Int16);
    EXPECT_EQ(v.name(), "tiny");
    EXPECT_EQ(v.voxel_count(), 6u);
    EXPECT_EQ(v.min_value(), -2.0f);
    EXPECT_EQ(v.max_value(), 7.0f);
}

TEST(Volume, IndexOrderIsXFastestThenYThenZ) {
    std::vector<float> samples(2 * 3 * 4);
    for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<float>(i);
    const Volume v({2, 3, 4}, glm::vec3(1.0f), ScalarType::Float32, samples);
    EXPECT_EQ(v.at(1, 0, 0), 1.0f);
    EXPECT_EQ(v.at(0, 1, 0), 2.0f);
    EXPECT_EQ(v.at(0, 0, 1), 6.0f);
    EXPECT_EQ(v.at(1, 2, 3), 23.0f);
}

TEST(Volume, AtClampedHoldsEdgeValuesOutsideTheGrid) {
    std::vector<float> samples(2 * 3 * 4);
    for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<float>(i);
    const Volume v({2, 3, 4}, glm::vec3(1.0f), ScalarType::Float32, samples);
    EXPECT_EQ(v.at_clamped(-5, 0, 0), v.at(0, 0, 0));
    EXPECT_EQ(v.at_clamped(7, 9, 11), v.at(1, 2, 3));
    EXPECT_EQ(v.at_clamped(1, -1, 2), v.at(1, 0, 2));
    EXPECT_EQ(v.at_clamped(1, 1, 1), v.at(1, 1, 1));
}

TEST(Volume, RejectsInconsistentConstruction) {
    EXPECT_THROW(Volume({2, 2, 2}, glm::vec3(1.0f), ScalarType::UInt8, std::vector<float>(7)), std::invalid_argument);
    EXPECT_THROW(Volume({0, 2, 2}, glm::vec3(1.0f), ScalarType::UInt8, {}), std::invalid_argument);
    EXPECT_THROW(Volume({1, 1, 1}, {1.0f, 0.0f, 1.0f}, ScalarType::UInt8, {1.0f}), std::invalid_argument);
    EXPECT_THROW(Volume({1, 1, 1}, {1.0f, 1.0f, std::nanf("")}, ScalarType::UInt8, {1.0f}), std::invalid_argument);
}

TEST(Volume, RangeLeavesOutNaNSamples) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Volume v({4, 1, 1}, glm::vec3(1.0f), ScalarType::Float32, {nan, 4.0f, -1.0f, nan});
    EXPECT_EQ(v.min_value(), -1.0f);
    EXPECT_EQ(v.max_value(), 4.0f);
}

TEST(Volume, DefaultIsEmpty) {
    const Volume v;
    EXPECT_EQ(v.voxel_count(), 0u);
    EXPECT_EQ(v.dims(), glm::ivec3(0));
}

TEST(Volume, SetNameRenames) {
    Volume v({1, 1, 1}, glm::vec3(1.0f), ScalarType::UInt8, {5.0f}, "a");
    v.set_name("b");
    EXPECT_EQ(v.name(), "b");
}

}  // namespace
}  // namespace pp5
