#pragma once
// Wilson, Ma and McCormick's hybrid volume and point rendering (2002) as a kernel of the simulated
// Pixel-planes 5: a low-resolution copy of the volume sits in the PPs' voxel store, which classifies
// and shades it; the GPs own its bricks and the points where its reconstruction misses the original;
// the renderers draw its axis-aligned slices back to front with the points between them. See
// hybrid_volume.h and hybrid_slicer.h.

#include "kernels/api/kernel.h"

namespace pp5 {

const Kernel& wilson_kernel();

}  // namespace pp5
