#pragma once
// The configuration of a run: every machine parameter plus the parameters of the kernels that run on
// it ("levoy.*"), read from a machine file with --set overrides.

#include "frontends/scenario.h"
#include "kernels/levoy/levoy_renderer.h"
#include "kernels/reference/reference_renderer.h"
#include "sim/core/config.h"

#include <string>
#include <vector>

namespace pp5 {

std::vector<const ParamGroup*> run_param_groups();

// Defaults, then the machine file (a path or a preset name), then each "key=value" override.
MachineConfig load_run_config(const std::string& machine, const std::vector<std::string>& overrides);

// How a scenario's frames become the Levoy kernel's inputs: its image settings, and each frame's camera
// (an orbit about the volume's bounding sphere) with what changed.
LevoyImageSettings levoy_image_settings(const ImageSpec& image);
RenderSettings reference_render_settings(const ImageSpec& image);
Camera frame_camera(const FrameSpec& frame, const Volume& volume);
LevoyFrameInputs levoy_frame_inputs(const FrameSpec& frame, const Volume& volume);

}  // namespace pp5
