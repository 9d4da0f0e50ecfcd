#include "scene/render/shading.h"
#include "sim/core/input_error.h"
#include "tests/support/vector_expectations.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

namespace pp5 {
namespace {

using test::expect_near;

const glm::vec3 kBase{0.8f, 0.6f, 0.4f};
const glm::vec3 kZ{0.0f, 0.0f, 1.0f};

TEST(Phong, AmbientOnlyWithoutANormal) {
    const PhongLighting l;
    expect_near(phong_shade(l, kBase, glm::vec3(0.0f), kZ, kZ, 0.3f), kBase * l.ambient);
}

TEST(Phong, FacingTheLightAndViewer) {
    PhongLighting l;
    l.ambient = 0.1f;
    l.diffuse = 0.6f;
    l.specular = 0.3f;
    // N = L = V: N.L = N.H = 1.
    expect_near(phong_shade(l, kBase, kZ, kZ, kZ, 0.0f), kBase * (0.1f + 0.6f + 0.3f));
}

TEST(Phong, HandComputedObliqueLight) {
    PhongLighting l;
    l.ambient = 0.2f;
    l.diffuse = 0.5f;
    l.specular = 0.4f;
    l.shininess = 4.0f;
    const glm::vec3 n = kZ;
    const glm::vec3 light = glm::normalize(glm::vec3(0.0f, std::sqrt(3.0f), 1.0f));  // 60 degrees off N
    const glm::vec3 viewer = kZ;
    // N.L = 0.5; H bisects 0 and 60 degrees: N.H = cos 30.
    const float n_dot_h = std::cos(glm::radians(30.0f));
    const glm::vec3 expected = kBase * 0.2f + kBase * (0.5f * 0.5f + 0.4f * std::pow(n_dot_h, 4.0f));
    expect_near(phong_shade(l, kBase, n, light, viewer, 0.0f), expected);
}

TEST(Phong, FacingAwayGetsAmbientOnly) {
    const PhongLighting l;
    expect_near(phong_shade(l, kBase, -kZ, kZ, kZ, 0.0f), kBase * l.ambient);
}

TEST(Phong, DepthCueDividesDiffuseAndSpecular) {
    PhongLighting l;
    l.ambient = 0.1f;
    l.diffuse = 0.6f;
    l.specular = 0.3f;
    l.depth_cue_k1 = 1.0f;
    l.depth_cue_k2 = 1.0f;
    // d = 1: divisor k1 + k2 = 2; ambient untouched.
    expect_near(phong_shade(l, kBase, kZ, kZ, kZ, 1.0f), kBase * (0.1f + 0.9f / 2.0f));
    expect_near(phong_shade(l, kBase, kZ, kZ, kZ, 0.5f), kBase * (0.1f + 0.9f / 1.5f));
}

TEST(PhongShader, WholeExponentsMatchStdPow) {
    for (float n : {0.0f, 1.0f, 7.0f, 20.0f, 128.0f, 2.5f}) {
        PhongLighting l;
        l.ambient = 0.0f;
        l.diffuse = 0.0f;
        l.specular = 1.0f;
        l.shininess = n;
        const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
        const glm::vec3 h = glm::normalize(light + kZ);
        const float expected = std::pow(glm::dot(kZ, h), n);
        const glm::vec3 c = PhongShader(l).shade(glm::vec3(1.0f), kZ, light, kZ, 0.0f);
        EXPECT_NEAR(c.r, expected, 2e-6f * std::max(1.0f, expected)) << "n = " << n;
    }
}

TEST(PhongShader, HeadlightMatchesTheGeneralFormula) {
    const PhongLighting l;
    const PhongShader shader(l);
    for (const glm::vec3 n : {glm::normalize(glm::vec3(0.2f, -0.4f, 1.0f)), glm::normalize(glm::vec3(1.0f, 1.0f, 0.1f)),
                              glm::vec3(0.0f), -kZ}) {
        expect_near(shader.shade_headlight(kBase, n, kZ, 0.25f), shader.shade(kBase, n, kZ, kZ, 0.25f), 1e-6f);
    }
}

// Each stationary light adds what it would give alone, scaled by its intensity; the ambient term is
// counted once, and the depth cue divides the sum.
TEST(PhongShader, StationaryLightsAddTheirOwnTerms) {
    PhongLighting key;
    key.light_follows_camera = false;
    key.light_direction = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
    key.depth_cue_k2 = 0.5f;
    PhongLighting all = key;
    all.stationary_lights = {{glm::vec3(-1.0f, 0.5f, 1.0f), 0.4f}, {glm::vec3(0.0f, 2.0f, 1.0f), 1.0f}};
    const PhongShader shader(all);
    const PhongShader key_only(key);
    for (const glm::vec3 n :
         {glm::normalize(glm::vec3(0.2f, -0.4f, 1.0f)), glm::normalize(glm::vec3(-1.0f, 1.0f, 0.1f)), kZ}) {
        glm::vec3 expected = key_only.shade(kBase, n, key.light_direction, kZ, 0.6f);
        for (const StationaryLight& light : all.stationary_lights) {
            PhongLighting one = key;
            one.ambient = 0.0f;
            one.diffuse *= light.intensity;
            one.specular *= light.intensity;
            expected += PhongShader(one).shade(kBase, n, glm::normalize(light.direction), kZ, 0.6f);
        }
        expect_near(shader.shade(kBase, n, key.light_direction, kZ, 0.6f), expected, 1e-5f);
    }
    // A face the key light does not reach (N.L < 0) is still lit by a stationary light that does.
    const glm::vec3 up = glm::normalize(glm::vec3(0.0f, 1.0f, -0.3f));
    ASSERT_LT(glm::dot(up, key.light_direction), 0.0f);
    EXPECT_EQ(key_only.shade(kBase, up, key.light_direction, kZ, 0.0f), kBase * key.ambient);
    EXPECT_GT(shader.shade(kBase, up, key.light_direction, kZ, 0.0f).r, kBase.r * key.ambient + 0.05f);
    // With a headlight too.
    PhongLighting head = all;
    head.light_follows_camera = true;
    const PhongShader headlight(head);
    const glm::vec3 n = glm::normalize(glm::vec3(0.5f, 0.5f, 0.7f));
    expect_near(headlight.shade_headlight(kBase, n, kZ, 0.3f), headlight.shade(kBase, n, kZ, kZ, 0.3f), 1e-6f);
}

TEST(Phong, ValidationRejectsBadLighting) {
    EXPECT_NO_THROW(validate_lighting(PhongLighting{}));
    PhongLighting negative;
    negative.diffuse = -0.1f;
    EXPECT_THROW(validate_lighting(negative), InputError);
    PhongLighting cue;
    cue.depth_cue_k1 = 1.0f;
    cue.depth_cue_k2 = -1.0f;  // divisor 0 at d = 1
    EXPECT_THROW(validate_lighting(cue), InputError);
    PhongLighting no_light;
    no_light.light_follows_camera = false;
    no_light.light_direction = glm::vec3(0.0f);
    EXPECT_THROW(validate_lighting(no_light), InputError);
    PhongLighting dark_stationary;
    dark_stationary.stationary_lights = {{glm::vec3(0.0f, 0.0f, 1.0f), 1.0f}, {glm::vec3(1.0f, 0.0f, 0.0f), -0.5f}};
    try {
        validate_lighting(dark_stationary);
        ADD_FAILURE() << "a negative intensity was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "lighting.stationary_lights[1].intensity");
    }
    PhongLighting pointless;
    pointless.stationary_lights = {{glm::vec3(0.0f), 1.0f}};
    EXPECT_THROW(validate_lighting(pointless), InputError);
}

}  // namespace
}  // namespace pp5
