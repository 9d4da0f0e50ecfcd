#pragma once
// Phong shading with depth cueing, as Levoy uses it:
//   c = c_p k_a + c_p / (k1 + k2 d) [ k_d (N.L) + k_s (N.H)^n ]
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

namespace pp5 {

struct PhongLighting {
    float ambient = 0.15f;          // k_a
    float diffuse = 0.7f;           // k_d
    float specular = 0.3f;          // k_s
    float shininess = 20.0f;        // n
    glm::vec3 light_direction{0.0f, 0.0f, -1.0f};  // world space, towards the light (normalised on use)
    bool light_follows_camera = true;               // a headlight: L = V, light_direction ignored
    float depth_cue_k1 = 1.0f;
    float depth_cue_k2 = 0.0f;      // 0 disables depth cueing

    bool operator==(const PhongLighting&) const = default;
};

// Throws pp5::InputError (field "lighting.*") for negative coefficients, a zero light direction
// (unless the light follows the camera), or depth cueing whose divisor k1 + k2 d is not positive
// over d in [0,1].
void validate_lighting(const PhongLighting& lighting);

// Whether voxel colours depend on where the observer is: a headlight, a highlight or depth cueing.
bool shading_depends_on_view(const PhongLighting& lighting);

// Shade one voxel. base = c_p; normal may be zero (no gradient); to_light and to_viewer are unit.
glm::vec3 phong_shade(const PhongLighting& lighting, glm::vec3 base, glm::vec3 normal,
                      glm::vec3 to_light, glm::vec3 to_viewer, float depth);

// The same formula with the per-lighting work done once, for shading millions of voxels: inline, and
// (N.H)^n by repeated squaring when n is a whole number up to 1024 (within a few ulps of std::pow).
class PhongShader {
public:
    explicit PhongShader(const PhongLighting& lighting)
        : lighting_(lighting), integer_exponent_(whole_exponent(lighting.shininess)) {}

    const PhongLighting& lighting() const { return lighting_; }

    glm::vec3 shade(glm::vec3 base, glm::vec3 normal, glm::vec3 to_light, glm::vec3 to_viewer, float depth) const {
        const glm::vec3 ambient = base * lighting_.ambient;
        if (normal == glm::vec3(0.0f)) return ambient;
        const float n_dot_l = glm::dot(normal, to_light);
        if (n_dot_l <= 0.0f) return ambient;  // one-sided: the light does not reach this face
        float highlight = 0.0f;
        const glm::vec3 halfway = to_light + to_viewer;
        const float halfway_length = glm::length(halfway);
        if (halfway_length > 0.0f) {
            const float n_dot_h = glm::dot(normal, halfway) / halfway_length;
            if (n_dot_h > 0.0f) highlight = lighting_.specular * power(n_dot_h);
        }
        const float attenuation = 1.0f / (lighting_.depth_cue_k1 + lighting_.depth_cue_k2 * depth);
        return ambient + base * (attenuation * (lighting_.diffuse * n_dot_l + highlight));
    }

    // The same with the light at the viewer (L = V, hence H = V): one dot product instead of three.
    glm::vec3 shade_headlight(glm::vec3 base, glm::vec3 normal, glm::vec3 to_viewer, float depth) const {
        const glm::vec3 ambient = base * lighting_.ambient;
        const float n_dot_v = glm::dot(normal, to_viewer);
        if (n_dot_v <= 0.0f) return ambient;  // also a zero normal
        const float highlight = lighting_.specular * power(n_dot_v);
        const float attenuation = 1.0f / (lighting_.depth_cue_k1 + lighting_.depth_cue_k2 * depth);
        return ambient + base * (attenuation * (lighting_.diffuse * n_dot_v + highlight));
    }

private:
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

    PhongLighting lighting_;
    int integer_exponent_;  // -1: not a small whole number, use std::pow
};

}  // namespace pp5
