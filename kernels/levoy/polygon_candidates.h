#pragma once
// Which PPs the host must run a polygon's scan-conversion program on (geometry_programs.h): the rest
// fail every test before they could change anything, so PpArray::run_candidates counts them as the
// hardware runs them without running them.

#include "kernels/levoy/geometry_programs.h"

#include <span>
#include <vector>

namespace pp5 {

// The PPs of a slot that the polygon's program must run on (PpArray::run_candidates), ascending, into
// `out`: those whose voxel, moved by some subvoxel translation, lies within half a voxel of the plane
// as the QEE computes it from `expressions`. Every other PP fails each translation's first test, the
// plane's, and so the count test after them: a bystander of the program (sim/pixel_processors/pp_program.h),
// which the hardware still runs but which changes nothing. Exact: found from the same integers the QEE
// evaluates, row by row (a row whose values could wrap in their field is taken whole).
void polygon_candidates(const PreparedPolygon& polygon, int samples, const PpProgram& program,
                        std::span<const QeeCoefficients> expressions, const PpArrayShape& shape, std::vector<int>& out);

}  // namespace pp5
