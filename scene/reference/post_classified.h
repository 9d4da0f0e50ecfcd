#pragma once
// The other order: interpolate the value and the gradient at each sample, then classify and shade
// there (what VTK's ray casters do). Sharper surfaces than Levoy's order for the same sampling, but
// classification and shading run per sample instead of per voxel, and nothing can be kept across
// frames except the gradients and the block value ranges. Same rays, samples, opacity correction,
// compositing, early termination and exact empty-space skipping as composite() (composite.h).

#include "scene/reference/composite.h"
#include "scene/reference/gradient_field.h"
#include "scene/reference/occupancy_grid.h"
#include "scene/render/camera.h"
#include "scene/render/classification.h"
#include "scene/render/image.h"
#include "scene/render/shading.h"
#include "scene/volume/volume.h"

namespace pp5 {

// Builds the occupancy grid from the volume's block value ranges.
Image render_post_classified(const Volume& volume, const GradientField& gradients, const Classification& classification,
                             const ColorMap& color_map, const PhongLighting& lighting, const Camera& camera,
                             const CompositeSettings& settings, CompositeStats* stats = nullptr);
// With a grid from occupancy_from_value_ranges(compute_block_value_ranges(...), classification).
Image render_post_classified(const Volume& volume, const GradientField& gradients, const Classification& classification,
                             const ColorMap& color_map, const PhongLighting& lighting, const Camera& camera,
                             const CompositeSettings& settings, const OccupancyGrid& occupancy,
                             CompositeStats* stats = nullptr);

}  // namespace pp5
