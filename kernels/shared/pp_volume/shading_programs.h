#pragma once
// Levoy's classification and Phong shading written as pixel-processor programs: fixed-point, at the
// widths the PPs would use, over the value and gradient each PP holds for one voxel slot. The
// floating-point originals are scene/render/classification.h and shading.h; the comments in
// classification_program.cpp, shading_programs.cpp and program_parts.cpp say where each fixed-point
// step comes from and what it rounds.
//
// Both programs read the slot's record (voxel_record.h) and write their results back into it:
//   classification: value, gradient -> opacity (changes only with the classification)
//   shading:        value, gradient -> red, green, blue (changes with colours, lights and the view)
//   stationary lights: gradient -> their summed light (changes with those lights only)
// so changing the light reruns only shading, and changing the classification only classification.

#include "kernels/shared/pp_volume/voxel_placement.h"
#include "kernels/shared/pp_volume/voxel_record.h"
#include "scene/reference/shading_view.h"
#include "scene/render/classification.h"
#include "scene/render/shading.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_program.h"

#include <glm/vec3.hpp>

#include <array>
#include <functional>

namespace pp5 {

struct PpProgramInputs {
    VoxelRecordLayout layout;
    VoxelQuantization quantization;
    glm::vec3 spacing{1.0f};
    int local_memory_bits = 208;
};

PpProgram build_classification_program(const Classification& classification, const PpProgramInputs& inputs);

// Lighting is one-sided Phong with an optional depth cue, as the reference shades. Per voxel, the QEE
// gives what depends on the voxel's position (slot_expressions): its depth for depth cueing and,
// under perspective with a headlight, its direction to the eye. Under perspective with a fixed light,
// highlights use the view's central direction (those of a distant viewer).
//
// `rewrite`, when given, changes the gradient the program shades with (Levoy's capping at a region of
// interest, say): it gets the voxel's value code and its three gradient fields, replaces those it
// changes (releasing the old), may use QEE expressions from kShadingExpressions on, and leaves every PP
// enabled.
using GradientRewrite = std::function<void(PpProgramBuilder&, const PpField& value, std::array<PpField, 3>& gradient)>;
//
// Stationary lights are summed with the key light before the depth cue. When the record has a field
// for them (layout.stationary_light_bits > 0), the program adds the sum stored there by
// build_stationary_light_program instead of computing it: the caller reruns that program whenever
// the stationary lights, k_d, k_s, n, the view's direction (with a highlight) or the gradients change.
PpProgram build_shading_program(const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view,
                                const PpProgramInputs& inputs, const GradientRewrite& rewrite = {});

// Levoy's precomputed stationary lights: sum_i s_i [k_d (N.L_i) + k_s (N.H_i)^n] per voxel, in
// 1/256ths, saturating at the field's largest code, stored in the record's stationary-light field.
PpProgram build_stationary_light_program(const PhongLighting& lighting, const ShadingView& view,
                                         const PpProgramInputs& inputs, const GradientRewrite& rewrite = {});

// The QEE expressions of one slot frame, linear in PP column and row, with kQeeShift fraction bits:
//   kDepthExpression        256 x the depth in [0,1] that ShadingView::depth gives
//   kToEyeExpression + i    256 x component i of (eye - voxel) / |eye - centre|
inline constexpr int kQeeShift = 16;
inline constexpr int kDepthExpression = 0;
inline constexpr int kToEyeExpression = 1;
inline constexpr int kShadingExpressions = 4;  // how many slot_expressions gives
std::array<QeeCoefficients, 4> slot_expressions(const ShadingView& view, const SlotFrame& frame, glm::vec3 spacing);

}  // namespace pp5
