#pragma once
// GoogleTest expectations on GLM vectors.

#include <gtest/gtest.h>
#include <glm/vec3.hpp>

namespace pp5::test {

// Each component within `tolerance`; a failure names the component that differs.
inline void expect_near(glm::vec3 a, glm::vec3 b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

}  // namespace pp5::test
