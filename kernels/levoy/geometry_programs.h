#pragma once
// Levoy's 3D scan-conversion of polygons on the renderers, as PP programs. The host broadcasts a
// polygon; for each of J subvoxel translations every PP evaluates, through the QEE, the polygon's
// plane distance and edge functions at its voxel (linear in PP column and row within a slot, so one
// expression each) and counts the translations for which its voxel's sample point lies in the
// polygon's one-voxel sheet. The count over J is the voxel's coverage; the polygon's colour and
// opacity, linear over its plane (Gouraud), also come from the QEE; and the PP mattes the polygon
// over its voxel:
//   a_p = coverage x polygon opacity,  a = a_p + a_v (1 - a_p),  c = (c_p a_p + c_v a_v (1 - a_p)) / a.
// Full coverage of an opaque polygon gives the polygon's colour and opacity; no coverage changes nothing.

#include "kernels/shared/pp_volume/shading_programs.h"
#include "kernels/shared/pp_volume/voxel_placement.h"
#include "scene/render/polygon.h"
#include "scene/render/region_of_interest.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_program.h"

#include <array>
#include <compare>
#include <vector>

namespace pp5 {

// A sample point lies in the polygon's one-voxel sheet when its plane distance, in the QEE's fixed
// point, is at most this.
inline constexpr std::int64_t kPolygonSheetHalfWidth = std::int64_t{1} << (kQeeShift - 1);

// What a polygon's program depends on besides the machine: the subvoxel translations, the edges and the
// widths of the fields its values need over a volume of `dims` voxels. Polygons of one shape share one
// program (a mesh's thousands of triangles need a handful); only their QEE expressions differ.
struct PolygonProgramShape {
    int samples = 1;
    int distance_bits = 0;
    std::vector<int> edge_bits;      // per edge
    std::array<int, 4> code_bits{};  // the red, green, blue and opacity codes before clamping
    auto operator<=>(const PolygonProgramShape&) const = default;
};
PolygonProgramShape polygon_program_shape(const PreparedPolygon& polygon, int samples, glm::ivec3 dims,
                                          const VoxelRecordLayout& layout);

// The program for polygons of `shape`, or for one polygon with `samples` subvoxel translations over a
// volume of `dims` voxels.
PpProgram build_polygon_program(const PolygonProgramShape& shape, const PpProgramInputs& inputs);
PpProgram build_polygon_program(const PreparedPolygon& polygon, int samples, glm::ivec3 dims,
                                const PpProgramInputs& inputs);

// The slot's QEE expressions, in the program's order: for each translation j the plane distance then
// each edge function (kQeeShift fraction bits, in voxels), then red, green, blue and opacity as codes.
std::vector<QeeCoefficients> polygon_expressions(const PreparedPolygon& polygon, const std::vector<glm::dvec3>& offsets,
                                                 const SlotFrame& frame, const VoxelRecordLayout& layout);

// Whether a slot may hold a voxel the polygon reaches: its voxels' box against the polygon's box grown
// by one voxel. Slots that fail are not run (the controller skips them).
bool polygon_reaches_slot(const PreparedPolygon& polygon, const SlotFrame& frame, glm::ivec3 dims,
                          const PpArrayShape& shape);

// Levoy's volume-of-interest tool as a PP program run after classification: each PP finds its voxel's
// distance to the region's surface (box: three linear QEE expressions; ellipsoid: one quadratic), the
// factor across the transition, and scales its opacity, all in fixed point (distance in 1/256 voxel,
// factor in 1/256). At scale 1 inside and out the factor is exactly 1 and no opacity changes.
PpProgram build_region_program(const RegionOfInterest& region, glm::ivec3 dims, const PpProgramInputs& inputs);
std::vector<QeeCoefficients> region_expressions(const RegionOfInterest& region, const SlotFrame& frame);

// Levoy's capping for a box region (his Figure 6): the voxels in the transition zone are shaded as if
// the region held air, so the structures it cuts through are capped where they enter it. Each face
// whose transition band holds the voxel (its face distance within half the transition of the surface,
// and the voxel not beyond the band outside) counts the voxel's neighbour across that face, towards
// the region, as air: along the face's outward normal n the central difference becomes
// (f(x + n) - f_air) / 2, to first order g.n + (f - f_air - g.n) / 2, with f_air the volume's lowest
// value (value code 0). A rewrite for build_shading_program; the region's box coordinates are QEE
// expressions first_expression to first_expression + 2 (region_expressions' order). A voxel outside
// every band is shaded as before.
GradientRewrite region_cap(const RegionOfInterest& region, glm::ivec3 dims, const PpProgramInputs& inputs,
                           int first_expression);

// The first step of rebuilding Levoy's pyramid of binary volumes, after a classification that changes
// which voxels are empty: each PP sets its voxel's bit (non-empty when its opacity code is not zero),
// which the renderer then reads out and broadcasts to the GPs, a slot's bit plane a message.
PpProgram build_emptiness_program(const PpProgramInputs& inputs);

// Coverage counts as the PPs compute them, on the host in double precision: the oracle for tests.
int host_coverage(const PreparedPolygon& polygon, const std::vector<glm::dvec3>& offsets, glm::ivec3 voxel);

}  // namespace pp5
