#pragma once
// A kernel of the test tree's own, as small as a kernel can be, to show that a kernel is one folder and
// one registration: it paints horizontal stripes in two passes and asks the machine for real work (a
// broadcast from the renderers, then a GP task per row whose items shade a pixel after fetching a
// block), declaring its own parameters, operation costs and metric.

#include "kernels/api/kernel.h"

namespace pp5::test {

const Kernel& dummy_kernel();

}  // namespace pp5::test
