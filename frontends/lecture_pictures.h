#pragma once
// Pictures a lecture needs beside a frame, made from what the frame already computed: its refinement
// passes side by side (and as an animated GIF), a map of which GP cast which screen tile, from the
// timing engine's own record of who ran each task, and the components' utilisation over time, from the
// busy spans the trace recorder keeps.

#include "frontends/plot.h"
#include "scene/render/image.h"
#include "sim/core/trace_recorder.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

// The passes left to right, a few background pixels apart.
Image passes_strip(const std::vector<Image>& passes);

// Each tile of the GP phase `phase_name` tinted by the GP that ran it (the one that cast most of its
// rays over the passes), over the frame's brightness, with the tiles' edges drawn; nullopt when that
// phase's tasks are not screen tiles.
std::optional<Image> gp_tile_map(const FrameWork& work, const FrameTiming& timing, std::size_t gp_count,
                                 const Image& frame, const std::string& phase_name = "ray_casting");

// One frame's timeline as lanes of time bins, one lane per GP, renderer, ring channel and the like,
// from the slices a trace recorder kept (keep_slices) while the frame was timed: what a page draws.
struct TimelineLane {
    std::string group;        // "GPs", "renderers", "ring", ...
    std::string name;         // the component
    std::vector<float> busy;  // per bin: the part of it the component was busy ("waiting" is idle)
    std::vector<int>
        what;  // per bin: the activity (index into FrameTimeline::activities) that took most of it, -1 if idle
};
struct FrameTimeline {
    Tick start_ps = 0;
    Tick end_ps = 0;
    int bins = 0;
    std::vector<std::string> activities;
    std::vector<TimelineLane> lanes;  // grouped: GPs, renderers, ring, then the rest, each group in the order given
    std::size_t slices_dropped = 0;   // slices past the recorder's limit, not drawn
};
// `components` are the (group, name) of the lanes wanted (Machine::trace_track_names of the machine
// that timed the frame): a lane for each, busy or not, grouped as above; a group none of whose
// components did anything in the frame is left out.
FrameTimeline frame_timeline(const TraceRecorder& trace, const FrameTiming& timing,
                             const std::vector<std::pair<std::string, std::string>>& components, int bins = 480);

// How busy each kind of component was over [start, end), in `bins` slices of time: for each group the
// trace recorded busy spans for (keep_busy_spans), busy time in the bin over `counts[group]` x the bin.
PlotSpec utilisation_over_time(const TraceRecorder& trace, Tick start, Tick end,
                               const std::map<std::string, std::size_t>& counts, int bins = 120);

}  // namespace pp5
