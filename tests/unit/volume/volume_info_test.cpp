// describe_volume: the lines `pp5sim volume-info` prints.

#include "scene/volume/volume_info.h"
#include "scene/volume/phantoms.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace pp5 {
namespace {

using ::testing::HasSubstr;

TEST(DescribeVolume, NamesShapeTypeAndValues) {
    const std::string text = describe_volume(make_sphere_phantom(32));
    EXPECT_THAT(text, HasSubstr("name:        sphere\n"));
    EXPECT_THAT(text, HasSubstr("32 x 32 x 32 (32,768 voxels)"));
    EXPECT_THAT(text, HasSubstr("spacing:     1 x 1 x 1 mm"));
    EXPECT_THAT(text, HasSubstr("extent:      32 x 32 x 32 mm"));
    EXPECT_THAT(text, HasSubstr("uint8 (32.0 KiB as stored, 128.0 KiB as float samples)"));
    EXPECT_THAT(text, HasSubstr("values:      0 .. 200"));
    EXPECT_THAT(text, HasSubstr("zero voxels:"));
    EXPECT_THAT(text, HasSubstr("percentiles: 50% 0"));  // the ball fills about 18% of the box
    EXPECT_EQ(text.back(), '\n');
}

TEST(DescribeVolume, StatisticsOfAKnownVolume) {
    // Half 100, half 200: mean 150, std dev 50, no zeros, median 100 (lower), 90% 200.
    const std::string text = describe_volume(make_checker_box_phantom(20, 10));
    EXPECT_THAT(text, HasSubstr("mean 150, std dev 50"));
    EXPECT_THAT(text, HasSubstr("zero voxels: 0.0% (8,000 non-zero)"));
    EXPECT_THAT(text, HasSubstr("90% 200"));
}

TEST(DescribeVolume, EmptyVolume) { EXPECT_THAT(describe_volume(Volume()), HasSubstr("empty volume")); }

}  // namespace
}  // namespace pp5
