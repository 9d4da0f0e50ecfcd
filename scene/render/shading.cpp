#include "scene/render/shading.h"

#include "sim/core/input_error.h"

#include <string>

namespace pp5 {

namespace {

bool non_negative(float x) { return x >= 0.0f && std::isfinite(x); }

}  // namespace

void validate_lighting(const PhongLighting& lighting) {
    if (!non_negative(lighting.ambient)) reject_field("lighting.ambient", "must be >= 0");
    if (!non_negative(lighting.diffuse)) reject_field("lighting.diffuse", "must be >= 0");
    if (!non_negative(lighting.specular)) reject_field("lighting.specular", "must be >= 0");
    if (!non_negative(lighting.shininess)) reject_field("lighting.shininess", "must be >= 0");
    if (!lighting.light_follows_camera && !(glm::length(lighting.light_direction) > 0.0f)) {
        reject_field("lighting.light_direction", "must be non-zero");
    }
    if (lighting.stationary_lights.size() > kMaxStationaryLights)
        reject_field("lighting.stationary_lights", "at most " + std::to_string(kMaxStationaryLights) + " lights");
    for (std::size_t i = 0; i < lighting.stationary_lights.size(); ++i) {
        const StationaryLight& light = lighting.stationary_lights[i];
        const std::string field = "lighting.stationary_lights[" + std::to_string(i) + "]";
        if (!(glm::length(light.direction) > 0.0f) || !std::isfinite(glm::length(light.direction)))
            reject_field(field + ".direction", "must be non-zero and finite");
        if (!non_negative(light.intensity) || light.intensity > kMaxLightIntensity)
            reject_field(field + ".intensity",
                         "must be in [0, " + std::to_string(static_cast<int>(kMaxLightIntensity)) + "]");
    }
    // k1 + k2 d is linear in d, so positive on [0,1] iff positive at both ends.
    const float near_divisor = lighting.depth_cue_k1;
    const float far_divisor = lighting.depth_cue_k1 + lighting.depth_cue_k2;
    if (!(near_divisor > 0.0f && far_divisor > 0.0f && std::isfinite(far_divisor))) {
        reject_field("lighting.depth_cue_k1", "k1 and k1 + k2 must be positive (the depth-cue divisor)");
    }
}

glm::vec3 phong_shade(const PhongLighting& lighting, glm::vec3 base, glm::vec3 normal, glm::vec3 to_light,
                      glm::vec3 to_viewer, float depth) {
    return PhongShader(lighting).shade(base, normal, to_light, to_viewer, depth);
}

bool shading_depends_on_view(const PhongLighting& lighting) {
    return lighting.light_follows_camera || lighting.specular > 0.0f || lighting.depth_cue_k2 != 0.0f;
}

}  // namespace pp5
