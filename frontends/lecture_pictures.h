#pragma once
// Pictures a lecture needs beside a frame, made from what the frame already computed: its refinement
// passes side by side (and as an animated GIF), and a map of which GP cast which screen tile, from the
// timing engine's own record of who ran each task.

#include "kernels/render/image.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

#include <optional>
#include <vector>

namespace pp5 {

// The passes left to right, a few background pixels apart.
Image passes_strip(const std::vector<Image>& passes);

// Each tile of the GP phase `phase_name` tinted by the GP that ran it (the one that cast most of its
// rays over the passes), over the frame's brightness, with the tiles' edges drawn; nullopt when that
// phase's tasks are not screen tiles.
std::optional<Image> gp_tile_map(const FrameWork& work, const FrameTiming& timing, std::size_t gp_count, const Image& frame,
                                 const std::string& phase_name = "ray_casting");

}  // namespace pp5
