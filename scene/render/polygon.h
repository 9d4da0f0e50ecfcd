#pragma once
// Polygons added to a volume (Levoy, "Rendering mixtures of geometric and volumetric data", as his
// workstation paper uses it): a planar convex polygon in voxel coordinates, with a colour and an opacity
// at each vertex (Gouraud), 3D scan-converted into the volume as a sheet one voxel thick.
//
// A voxel is a unit cube about its centre. A point lies in the polygon's sheet when its distance to the
// polygon's plane is at most half a voxel and it lies inside every edge. The voxel's coverage is the
// fraction of J subvoxel sample points, the voxel's centre moved by J fixed offsets, that lie in the
// sheet: summed over voxels it approaches the polygon's area (times one voxel of thickness) as J grows,
// and J = 1 (the centre alone) is a binary voxelisation.

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace pp5 {

struct PolygonSpec {
    std::vector<glm::vec3> vertices;  // voxel coordinates, in order round the polygon
    std::vector<glm::vec3> colors;    // one per vertex, or one for all
    std::vector<float> opacities;     // one per vertex, or one for all
};

// A linear function of position: value(p) = dot(gradient, p) + offset.
struct LinearFunction {
    glm::vec3 gradient{0.0f};
    float offset = 0.0f;
    float operator()(glm::vec3 p) const { return gradient.x * p.x + gradient.y * p.y + gradient.z * p.z + offset; }
};

// What scan conversion needs, in double precision: the plane, the edges' inward in-plane normals, and
// colour and opacity as linear functions over the plane (exact at a triangle's vertices, a least-squares
// fit for more).
struct PreparedPolygon {
    bool degenerate = false;  // no area: covers nothing
    double area = 0.0;
    glm::dvec3 normal{0.0};                // unit
    double plane_offset = 0.0;             // distance(p) = dot(normal, p) + plane_offset
    std::vector<glm::dvec3> edge_normals;  // unit, pointing inwards
    std::vector<double> edge_offsets;      // inside edge i when dot(edge_normals[i], p) + edge_offsets[i] >= 0
    LinearFunction red, green, blue, opacity;
    glm::vec3 lower{0.0f};  // bounding box of the vertices
    glm::vec3 upper{0.0f};

    double distance(glm::dvec3 p) const;
    bool in_sheet(glm::dvec3 p) const;  // the test every PP makes for each sample point
};

// The farthest a vertex may lie from the volume's origin, in voxels. The renderers evaluate plane and
// edge distances in fixed point (16 fraction bits, at most 48 bits a field), which holds distances of
// about 2^31 voxels; a hundred million leaves room for the volume's own extent.
inline constexpr double kFarthestPolygonVertex = 1e8;

// Checks a polygon: at least three finite vertices within kFarthestPolygonVertex, one colour and opacity per vertex or
// one for all, colours and opacities in [0, 1], the vertices in one plane (within 0.01 voxel) and convex. Throws
// InputError(file, field, reason). A polygon with no area is accepted (it covers nothing).
void validate_polygon(const PolygonSpec& polygon, const std::string& file, const std::string& field);
PreparedPolygon prepare_polygon(const PolygonSpec& polygon);
// The area of the part of a planar polygon inside the box [lower, upper] (clipped plane by plane):
// what a scan-converter that visits only the volume's voxels covers, however far the polygon reaches.
double area_inside_box(const std::vector<glm::vec3>& vertices, glm::dvec3 lower, glm::dvec3 upper);

// J fixed sample offsets in the voxel's cube [-1/2, 1/2)^3: the centre first, then a low-discrepancy
// (R3) sequence, so coverage error falls roughly as 1/J. J >= 1.
std::vector<glm::dvec3> subvoxel_offsets(int count);

}  // namespace pp5
