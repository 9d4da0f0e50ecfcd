#include "scene/render/region_of_interest.h"

#include "sim/core/input_error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

glm::vec3 RegionOfInterest::axis(int i) const {
    // Rotation R = Rz Ry Rx; the region's axes are R's columns, and local coordinates use R^T.
    const glm::vec3 r = glm::radians(rotation_degrees);
    const float cx = std::cos(r.x), sx = std::sin(r.x), cy = std::cos(r.y), sy = std::sin(r.y), cz = std::cos(r.z),
                sz = std::sin(r.z);
    const glm::vec3 columns[3] = {
        {cz * cy, sz * cy, -sy},
        {cz * sy * sx - sz * cx, sz * sy * sx + cz * cx, cy * sx},
        {cz * sy * cx + sz * sx, sz * sy * cx - cz * sx, cy * cx},
    };
    return columns[i];
}

glm::vec3 RegionOfInterest::local(glm::vec3 p) const {
    const glm::vec3 d = p - center;
    return {glm::dot(axis(0), d), glm::dot(axis(1), d), glm::dot(axis(2), d)};
}

float RegionOfInterest::distance(glm::vec3 p) const {
    const glm::vec3 q = local(p);
    if (shape == Shape::Box) {
        const glm::vec3 out = glm::abs(q) - half_size;
        return std::max({out.x, out.y, out.z});
    }
    const float s = glm::length(q / half_size);
    return (s - 1.0f) * std::min({half_size.x, half_size.y, half_size.z});
}

float RegionOfInterest::factor(glm::vec3 p) const {
    const float d = distance(p);
    float w = 0.0f;  // 0 inside, 1 outside
    if (transition <= 0.0f) w = d > 0.0f ? 1.0f : 0.0f;
    else w = std::clamp(d / transition + 0.5f, 0.0f, 1.0f);
    return scale_inside + (scale_outside - scale_inside) * w;
}

glm::vec3 RegionOfInterest::capped_gradient(glm::vec3 p, float value, glm::vec3 g, float air) const {
    if (!cap || shape != Shape::Box || !(transition > 0.0f)) return g;
    const glm::vec3 q = local(p);
    const float half_band = 0.5f * transition;
    glm::vec3 face;
    for (int i = 0; i < 3; ++i) face[i] = std::abs(q[i]) - half_size[i];
    if (std::max({face.x, face.y, face.z}) >= half_band) return g;  // beyond the band outside
    for (int i = 0; i < 3; ++i) {
        if (!(face[i] > -half_band)) continue;
        const glm::vec3 a = axis(i);
        const float side = q[i] < 0.0f ? -1.0f : 1.0f;
        g += a * (0.5f * (side * (value - air) - glm::dot(g, a)));
    }
    return g;
}

void validate_region(const RegionOfInterest& region, const std::string& file, const std::string& field) {
    for (int i = 0; i < 3; ++i) {
        if (!(region.half_size[i] > 0.0f) || !std::isfinite(region.half_size[i]))
            throw InputError(file, field + ".half_size", "every half size must be a positive number of voxels");
        if (!std::isfinite(region.center[i]) || !std::isfinite(region.rotation_degrees[i]))
            throw InputError(file, field + ".center", "the region's place and turn must be finite");
    }
    for (const auto& [name, v] :
         {std::pair{"scale_inside", region.scale_inside}, std::pair{"scale_outside", region.scale_outside}})
        if (!(v >= 0.0f && v <= 16.0f)) throw InputError(file, field + "." + name, "opacity scales lie in [0, 16]");
    if (!(region.transition >= 0.0f && region.transition <= 1000.0f))
        throw InputError(file, field + ".transition", "the transition is a width in voxels, from 0 to 1000");
    if (region.cap && region.shape != RegionOfInterest::Shape::Box)
        throw InputError(file, field + ".cap", "capping is for a box region (its faces give the caps' normals)");
    if (region.cap && !(region.transition > 0.0f))
        throw InputError(file, field + ".cap",
                         "capping recolours the transition zone: give the region a transition wider than 0");
}

}  // namespace pp5
