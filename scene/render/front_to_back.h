#pragma once
// Front-to-back compositing along one ray (Levoy: C += (1 - A) a c, A += (1 - A) a), shared by every
// kernel so that the simulated machine and the reference renderer blend samples identically.

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

class FrontToBack {
public:
    // sample_step: samples per voxel step. Opacities are classified per unit step, so other steps
    // correct them to keep a surface's look independent of the sampling rate.
    // termination_opacity: the ray is finished once its opacity reaches it (above 1: never).
    FrontToBack(float sample_step, float termination_opacity)
        : step_(sample_step), correct_(sample_step != 1.0f), stop_at_(termination_opacity) {}

    // Blends one sample behind what the ray has gathered; true when the ray is now finished.
    bool add(glm::vec3 sample_color, float alpha) {
        alpha = std::clamp(alpha, 0.0f, 1.0f);
        if (alpha <= 0.0f) return false;
        if (correct_) alpha = 1.0f - std::pow(1.0f - alpha, step_);
        const float weight = (1.0f - opacity_) * alpha;
        color_ += weight * sample_color;
        opacity_ += weight;
        return opacity_ >= stop_at_;
    }

    float opacity() const { return opacity_; }
    // The ray's colour over a background, with its opacity.
    glm::vec4 over(glm::vec3 background) const { return glm::vec4(color_ + (1.0f - opacity_) * background, opacity_); }

private:
    float step_;
    bool correct_;
    float stop_at_;
    glm::vec3 color_{0.0f};
    float opacity_ = 0.0f;
};

}  // namespace pp5
