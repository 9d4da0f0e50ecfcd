#pragma once
// What shading needs to know about the view: the direction to the viewer V and the depth d used for
// depth cueing. Two views that agree here give identical voxel colours (so a zoom or a change of image
// size does not reshade).

#include "scene/render/camera.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

struct ShadingView {
    Projection projection = Projection::Parallel;
    glm::vec3 eye{0.0f};
    glm::vec3 forward{0.0f, 0.0f, 1.0f};  // unit, from the eye into the scene
    glm::vec3 center{0.0f};               // of the volume's bounding sphere (world space)
    float radius = 0.0f;

    // Unit direction from a world point towards the viewer: constant for parallel projection; for
    // perspective, towards the eye (the view direction where the point is the eye itself).
    glm::vec3 to_viewer(glm::vec3 point) const {
        if (projection == Projection::Parallel) return -forward;
        const glm::vec3 towards = eye - point;
        const float distance_squared = glm::dot(towards, towards);
        return distance_squared > 0.0f ? towards * (1.0f / std::sqrt(distance_squared)) : -forward;
    }

    // Depth in [0,1] across the bounding sphere along the view direction: 0 at the near pole.
    float depth(glm::vec3 point) const {
        if (radius <= 0.0f) return 0.0f;
        return std::clamp((glm::dot(point - center, forward) + radius) / (2.0f * radius), 0.0f, 1.0f);
    }

    bool operator==(const ShadingView&) const = default;
};

// The view of a volume of `dims` voxels and `spacing` (box from 0 to (dims-1) * spacing).
inline ShadingView make_shading_view(const Camera& camera, glm::ivec3 dims, glm::vec3 spacing) {
    const glm::vec3 extent = glm::vec3(dims - 1) * spacing;
    ShadingView view;
    view.projection = camera.projection;
    view.forward = camera.forward();
    // The eye matters to parallel shading only through `forward`; leave it out so it does not reshade.
    view.eye = camera.projection == Projection::Perspective ? camera.eye : glm::vec3(0.0f);
    view.center = 0.5f * extent;
    view.radius = 0.5f * glm::length(extent);
    return view;
}

}  // namespace pp5
