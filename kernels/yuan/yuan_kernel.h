#pragma once
// Yuan, Nguyen, Xu and Chen's hybrid forward resampling (2003) as a kernel of the simulated
// Pixel-planes 5: the PPs classify and shade the voxels they hold (the shared voxel store), the GPs
// turn their bricks' non-transparent voxels into splats and points, and the renderers draw them over
// their screen regions. See hybrid_splatter.h.

#include "kernels/api/kernel.h"

namespace pp5 {

const Kernel& yuan_kernel();

}  // namespace pp5
