#include "sim/core/spelling.h"

#include <gtest/gtest.h>

namespace pp5 {
namespace {

TEST(Spelling, EditDistanceCountsTheSlipsOfTyping) {
    EXPECT_EQ(edit_distance("render", "render"), 0u);
    EXPECT_EQ(edit_distance("rendr", "render"), 1u);   // a letter left out
    EXPECT_EQ(edit_distance("redner", "render"), 1u);  // two neighbours swapped
    EXPECT_EQ(edit_distance("", "abc"), 3u);
}

TEST(Spelling, SuggestsOnlyANearMiss) {
    const std::vector<std::string> datasets{"ch2", "ch2better", "brainsmall", "ct-head"};
    EXPECT_EQ(closest_name("ct-hed", datasets), "ct-head");
    EXPECT_EQ(did_you_mean("brainsmal", datasets), "; did you mean brainsmall?");
    EXPECT_EQ(closest_name("lobster", datasets), "");  // nothing like it: no guess
    EXPECT_EQ(did_you_mean("lobster", datasets), "");
}

}  // namespace
}  // namespace pp5
