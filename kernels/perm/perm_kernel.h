#pragma once
// Lim and Shin's PERM ray casting as a kernel of the simulated Pixel-planes 5: the structure's records
// sit in the renderers' backing store (or in every GP's memory), the GPs cast rays through it,
// fetching each cell's record through their caches, and classify, shade and composite each sample
// from the looked-up values. See perm_structure.h and perm_ray_caster.h.

#include "kernels/api/kernel.h"

namespace pp5 {

const Kernel& perm_kernel();

}  // namespace pp5
