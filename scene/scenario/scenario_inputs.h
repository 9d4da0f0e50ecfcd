#pragma once
// What every kernel derives from a scenario in the same way: a frame's camera (an orbit about the
// volume's bounding sphere), and the reference renderer's settings and counts (the oracle every
// kernel's pictures are compared with).

#include "scene/reference/reference_renderer.h"
#include "scene/render/camera.h"

#include <nlohmann/json_fwd.hpp>
#include "scene/scenario/scenario.h"
#include "scene/volume/volume.h"

namespace pp5 {

Camera frame_camera(const FrameSpec& frame, const Volume& volume);
RenderSettings reference_render_settings(const ImageSpec& image);
// A reference render's counts, as stats.json's frame records give them.
nlohmann::json reference_stats(const RenderStats& stats);

}  // namespace pp5
