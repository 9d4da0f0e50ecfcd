#pragma once
// Levoy's volume-of-interest tool: a box or an ellipsoid, placed and turned anywhere in the volume,
// whose inside and outside have their opacities scaled (to highlight a region, or to cut into it),
// with a linear transition a few voxels wide across its surface so that the cut does not alias.
//
// The distance used for the transition is exact across a box's faces (the largest of the three
// face distances) and, for an ellipsoid, the distance scaled by its smallest radius
// ((sqrt(sum (q_i / r_i)^2) - 1) x min r), exact for a sphere.

#include <glm/vec3.hpp>

#include <string>

namespace pp5 {

struct RegionOfInterest {
    enum class Shape { Box, Ellipsoid };
    Shape shape = Shape::Box;
    glm::vec3 center{0.0f};            // voxel coordinates
    glm::vec3 half_size{10.0f};        // half edges of the box, or the ellipsoid's radii, in voxels
    glm::vec3 rotation_degrees{0.0f};  // about x, then y, then z
    float scale_inside = 1.0f;         // opacity factors, in [0, 16]
    float scale_outside = 1.0f;
    float transition = 2.0f;  // voxels across the surface; 0 is a hard edge
    bool cap = false;         // shade the transition zone as if the region held air (boxes only)

    bool operator==(const RegionOfInterest&) const = default;

    // The region's frame: q = rows(rotation) . (p - center).
    glm::vec3 local(glm::vec3 p) const;
    glm::vec3 axis(int i) const;  // row i of the rotation: the region's i-th axis in voxel space
    // Signed distance estimate in voxels: negative inside.
    float distance(glm::vec3 p) const;
    // The opacity factor at p: scale_inside inside, scale_outside outside, linear across the transition.
    float factor(glm::vec3 p) const;
    // Capping (boxes with `cap`): the gradient a voxel at p with value `value` and gradient g is shaded
    // with, as if the region held air of value `air`. For each face whose transition band holds p (and
    // p not beyond the band outside), the neighbour across that face towards the region counts as air:
    // along the face's outward normal n the central difference becomes (f(p + n) - air) / 2, to first
    // order g.n + (value - air - g.n) / 2, faces taken in axis order. Elsewhere g itself.
    glm::vec3 capped_gradient(glm::vec3 p, float value, glm::vec3 g, float air) const;
};

// Throws InputError(file, field, reason) for a non-positive size, scales outside [0, 16], or a
// negative transition, or capping asked of an ellipsoid or of a region without a transition.
void validate_region(const RegionOfInterest& region, const std::string& file, const std::string& field);

}  // namespace pp5
