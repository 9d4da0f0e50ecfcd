#pragma once
// Colour of one point of the volume from its value and gradient: base colour from the colour map,
// Phong shading with the normal from the gradient, clamped to [0,1]. The one shading rule used both
// at the voxels (shade-then-interpolate) and at interpolated samples (interpolate-then-shade).

#include "scene/reference/shading_view.h"
#include "scene/render/classification.h"
#include "scene/render/shading.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace pp5 {

class SampleShader {
public:
    SampleShader(const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view, glm::vec3 spacing)
        : color_map_(color_map),
          phong_(lighting),
          view_(view),
          inverse_spacing_(1.0f / spacing),
          fixed_light_(glm::normalize(lighting.light_direction)),
          headlight_(lighting.light_follows_camera) {}

    // value: the scalar; gradient: value units per voxel; position: world space.
    glm::vec3 shade(float value, glm::vec3 gradient, glm::vec3 position) const {
        // The gradient per voxel becomes per mm before normalising, so the normal is right in
        // anisotropic volumes; N points out of dense material, against the gradient.
        const glm::vec3 world_gradient = gradient * inverse_spacing_;
        const float length_squared = glm::dot(world_gradient, world_gradient);
        const glm::vec3 normal =
            length_squared > 0.0f ? world_gradient * (-1.0f / std::sqrt(length_squared)) : glm::vec3(0.0f);
        const glm::vec3 to_viewer = view_.to_viewer(position);
        const glm::vec3 base = color_map_.color(value);
        const float depth = view_.depth(position);
        // A headlight makes H = V = L, so N.H = N.L: the same formula with the half-vector known.
        const glm::vec3 color = headlight_ ? phong_.shade_headlight(base, normal, to_viewer, depth)
                                           : phong_.shade(base, normal, fixed_light_, to_viewer, depth);
        return glm::clamp(color, 0.0f, 1.0f);
    }

private:
    const ColorMap& color_map_;
    PhongShader phong_;
    ShadingView view_;
    glm::vec3 inverse_spacing_;
    glm::vec3 fixed_light_;
    bool headlight_;
};

}  // namespace pp5
