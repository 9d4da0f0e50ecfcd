#pragma once
// Stage 2: classification at the voxels (Levoy's order: classify, then resample). Depends on the
// volume, its gradients and the classification; a change of view or lighting leaves it valid.

#include "kernels/reference/gradient_field.h"
#include "kernels/render/classification.h"
#include "kernels/volume/volume.h"

#include <vector>

namespace pp5 {

// The opacity of every voxel, Classification::opacity(value, |gradient|), in Volume::index order.
std::vector<float> classify_voxels(const Volume& volume, const GradientField& gradients,
                                   const Classification& classification);

}  // namespace pp5
