#pragma once
// Levoy's classification and Phong shading written as pixel-processor programs: fixed-point, at the
// widths the PPs would use, over the value and gradient each PP holds for one voxel slot. The
// floating-point originals are kernels/render/classification.h and shading.h; the comments in the
// .cpp say where each fixed-point step comes from and what it rounds.
//
// Both programs read the slot's record (voxel_record.h) and write their results back into it:
//   classification: value, gradient -> opacity (changes only with the classification)
//   shading:        value, gradient -> red, green, blue (changes with colours, lights and the view)
// so changing the light reruns only shading, and changing the classification only classification.

#include "kernels/levoy/voxel_placement.h"
#include "kernels/levoy/voxel_record.h"
#include "kernels/reference/shading_view.h"
#include "kernels/render/classification.h"
#include "kernels/render/shading.h"
#include "sim/renderer/pp_array.h"
#include "sim/renderer/pp_program.h"

#include <glm/vec3.hpp>

namespace pp5 {

struct PpProgramInputs {
    VoxelRecordLayout layout;
    VoxelQuantization quantization;
    glm::vec3 spacing{1.0f};
    int local_memory_bits = 208;
};

PpProgram build_classification_program(const Classification& classification, const PpProgramInputs& inputs);

// Lighting is one-sided Phong with an optional depth cue, as the reference shades. The direction to
// the viewer is the view's direction for every voxel (exact for parallel projection; under
// perspective the highlights are those of a distant viewer). With depth cueing the program asks the
// QEE for each voxel's depth: expression 0, from depth_expression().
PpProgram build_shading_program(const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view,
                                const PpProgramInputs& inputs);

// The QEE coefficients giving 256 x (the depth in [0,1] that ShadingView::depth gives) for the voxels
// of one slot frame, as a linear function of PP column and row. kDepthShift is the fixed-point shift.
inline constexpr int kDepthShift = 16;
QeeCoefficients depth_expression(const ShadingView& view, const SlotFrame& frame, glm::vec3 spacing);

}  // namespace pp5
