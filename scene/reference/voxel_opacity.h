#pragma once
// Stage 2: classification at the voxels (Levoy's order: classify, then resample). Depends on the
// volume, its gradients and the classification; a change of view or lighting leaves it valid.

#include "scene/reference/gradient_field.h"
#include "scene/render/classification.h"
#include "scene/render/region_of_interest.h"
#include "scene/volume/volume.h"

#include <vector>

namespace pp5 {

// The opacity of every voxel, Classification::opacity(value, |gradient|), in Volume::index order.
std::vector<float> classify_voxels(const Volume& volume, const GradientField& gradients,
                                   const Classification& classification);

// Levoy's volume-of-interest tool at the voxels, after classification: each voxel's opacity times the
// region's factor at its position (voxel coordinates), kept within [0, 1].
void scale_by_region(std::vector<float>& opacity, glm::ivec3 dims, const RegionOfInterest& region);

// The gradients a capping region has the voxels shaded with (RegionOfInterest::capped_gradient), air
// being the volume's lowest value, written into `capped` (whose storage a region moved frame after
// frame reuses).
void cap_gradients(const Volume& volume, const GradientField& gradients, const RegionOfInterest& region,
                   GradientField& capped);

}  // namespace pp5
