#pragma once
// The host's floating-point reference renderer as a kernel: it renders every frame on this computer and
// asks nothing of the simulated machine (simulated time 0). The oracle the machine's kernels are
// compared with, runnable like them.

#include "kernels/api/kernel.h"

namespace pp5 {

const Kernel& reference_kernel();

}  // namespace pp5
