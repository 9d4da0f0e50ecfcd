#pragma once
// Levoy's volume rendering workstation as a kernel (kernels/api/kernel.h): the scenario's frames
// become LevoyRenderer's inputs, and its reports become stats.json's account of each frame.

#include "kernels/api/kernel.h"
#include "kernels/levoy/levoy_renderer.h"

namespace pp5 {

const Kernel& levoy_kernel();

// How a scenario's frames become the kernel's inputs: its image settings, and each frame's camera
// (frame_camera, an orbit about the volume's bounding sphere) with what changed.
LevoyImageSettings levoy_image_settings(const ImageSpec& image);
LevoyFrameInputs levoy_frame_inputs(const FrameSpec& frame, const Volume& volume);

}  // namespace pp5
