#pragma once
// Phong shading with depth cueing, as Levoy uses it, summed over the lights:
//   c = c_p k_a + c_p / (k1 + k2 d) sum_i s_i [ k_d (N.L_i) + k_s (N.H_i)^n ]
// The first light (s = 1) is the one a sequence moves, or a headlight; the stationary lights are
// Levoy's "multiple light sources only one of which is moving": their sum does not change while only
// the first light moves, so a renderer may precompute it per voxel and add it on each frame.
// N is the unit normal (minus the normalised gradient, so it points out of dense material),
// L the unit direction towards the light, H the half-vector of L and V (towards the viewer),
// d the voxel's depth in [0,1] across the volume's bounding sphere (0 = nearest the viewer).
// A voxel with zero gradient has no normal and gets the ambient term only.
//
// Lighting is one-sided: N.L and N.H below zero count as zero (a surface facing away from the light
// gets the ambient term), and there is no highlight on a surface the light does not reach. The result
// is not clamped; it can exceed 1 where k_a + k_d + k_s > 1 (renderers clamp voxel colours to [0,1]).

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstddef>
#include <vector>

namespace pp5 {

// A light that stays put while a sequence moves the key light: a direction and a strength.
struct StationaryLight {
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // world space, towards the light (normalised on use)
    float intensity = 1.0f;                  // s: scales its diffuse and specular terms

    bool operator==(const StationaryLight&) const = default;
};

// The most stationary lights a scenario may give, and the strongest light: each light adds its own
// Phong terms to every shading, and its strength widens the PPs' fields that hold them.
constexpr std::size_t kMaxStationaryLights = 8;
constexpr float kMaxLightIntensity = 10.0f;

struct PhongLighting {
    float ambient = 0.15f;                         // k_a
    float diffuse = 0.7f;                          // k_d
    float specular = 0.3f;                         // k_s
    float shininess = 20.0f;                       // n
    glm::vec3 light_direction{0.0f, 0.0f, -1.0f};  // world space, towards the light (normalised on use)
    bool light_follows_camera = true;              // a headlight: L = V, light_direction ignored
    float depth_cue_k1 = 1.0f;
    float depth_cue_k2 = 0.0f;                       // 0 disables depth cueing
    std::vector<StationaryLight> stationary_lights;  // beside the key light above

    bool operator==(const PhongLighting&) const = default;
};

// Throws pp5::InputError (field "lighting.*") for negative coefficients, a zero light direction
// (unless the light follows the camera), more than kMaxStationaryLights stationary lights or one with a
// zero direction or an intensity outside [0, kMaxLightIntensity], or depth cueing whose divisor k1 + k2 d is not
// positive over d in [0,1].
void validate_lighting(const PhongLighting& lighting);

// Whether voxel colours depend on where the observer is: a headlight, a highlight or depth cueing.
bool shading_depends_on_view(const PhongLighting& lighting);

// Shade one voxel. base = c_p; normal may be zero (no gradient); to_light and to_viewer are unit.
glm::vec3 phong_shade(const PhongLighting& lighting, glm::vec3 base, glm::vec3 normal, glm::vec3 to_light,
                      glm::vec3 to_viewer, float depth);

// The same formula with the per-lighting work done once, for shading millions of voxels: inline, and
// (N.H)^n by repeated squaring when n is a whole number up to 1024 (within a few ulps of std::pow).
class PhongShader {
public:
    explicit PhongShader(const PhongLighting& lighting)
        : lighting_(lighting), integer_exponent_(whole_exponent(lighting.shininess)) {
        for (const StationaryLight& light : lighting.stationary_lights)
            stationary_.push_back({glm::normalize(light.direction), light.intensity});
    }

    const PhongLighting& lighting() const { return lighting_; }

    glm::vec3 shade(glm::vec3 base, glm::vec3 normal, glm::vec3 to_light, glm::vec3 to_viewer, float depth) const {
        const glm::vec3 ambient = base * lighting_.ambient;
        if (normal == glm::vec3(0.0f)) return ambient;
        const float lit = lit_by(normal, to_light, to_viewer) + stationary_lit(normal, to_viewer);
        if (lit <= 0.0f) return ambient;  // one-sided: no light reaches this face
        return ambient + base * (attenuation(depth) * lit);
    }

    // The same with the key light at the viewer (L = V, hence H = V): one dot product instead of three.
    glm::vec3 shade_headlight(glm::vec3 base, glm::vec3 normal, glm::vec3 to_viewer, float depth) const {
        const glm::vec3 ambient = base * lighting_.ambient;
        const float n_dot_v = glm::dot(normal, to_viewer);  // zero for a zero normal
        float lit = n_dot_v > 0.0f ? lighting_.diffuse * n_dot_v + lighting_.specular * power(n_dot_v) : 0.0f;
        if (normal != glm::vec3(0.0f)) lit += stationary_lit(normal, to_viewer);
        if (lit <= 0.0f) return ambient;
        return ambient + base * (attenuation(depth) * lit);
    }

    // sum_i s_i [k_d (N.L_i) + k_s (N.H_i)^n] over the stationary lights: what a renderer may keep.
    float stationary_lit(glm::vec3 normal, glm::vec3 to_viewer) const {
        float sum = 0.0f;
        for (const auto& light : stationary_) sum += light.intensity * lit_by(normal, light.to_light, to_viewer);
        return sum;
    }

private:
    // k_d (N.L) + k_s (N.H)^n where the light reaches the face, else 0 (no highlight either).
    float lit_by(glm::vec3 normal, glm::vec3 to_light, glm::vec3 to_viewer) const {
        const float n_dot_l = glm::dot(normal, to_light);
        if (n_dot_l <= 0.0f) return 0.0f;
        float highlight = 0.0f;
        const glm::vec3 halfway = to_light + to_viewer;
        const float halfway_length = glm::length(halfway);
        if (halfway_length > 0.0f) {
            const float n_dot_h = glm::dot(normal, halfway) / halfway_length;
            if (n_dot_h > 0.0f) highlight = lighting_.specular * power(n_dot_h);
        }
        return lighting_.diffuse * n_dot_l + highlight;
    }

    float attenuation(float depth) const { return 1.0f / (lighting_.depth_cue_k1 + lighting_.depth_cue_k2 * depth); }

    static int whole_exponent(float n) {
        return n >= 0.0f && n <= 1024.0f && n == std::floor(n) ? static_cast<int>(n) : -1;
    }

    float power(float x) const {
        if (integer_exponent_ < 0) return std::pow(x, lighting_.shininess);
        float result = 1.0f;
        for (int e = integer_exponent_; e > 0; e >>= 1) {
            if (e & 1) result *= x;
            x *= x;
        }
        return result;
    }

    struct UnitLight {
        glm::vec3 to_light;
        float intensity;
    };

    PhongLighting lighting_;
    int integer_exponent_;  // -1: not a small whole number, use std::pow
    std::vector<UnitLight> stationary_;
};

}  // namespace pp5
