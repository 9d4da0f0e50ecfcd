#pragma once
// Rendering a scenario on a configured machine, as every frontend does it (the CLI's `render`, and the
// Python module and browser tool to come): the scenario's kernel computes each frame and records its
// work, the timing engine times it on the machine, the reference renderer gives the oracle picture,
// and the images, stats.json and config.json are staged to appear whole or not at all.

#include "frontends/image_io.h"
#include "frontends/staged_output.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"
#include "sim/core/trace_recorder.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pp5 {

struct ScenarioRenderOptions {
    ImageFormat format = ImageFormat::Png;
    TraceRecorder* trace = nullptr;                                     // records the run when given
    std::function<void(std::size_t done, std::size_t total)> progress;  // after each frame
    // Also write each frame's lecture pictures (frontends/lecture_pictures.h): its refinement passes as
    // a strip and an animated GIF, and the map of which GP cast which tile.
    bool lecture_pictures = false;
    // Compare every frame with the host reference renderer (PSNR, difference images). Off for big
    // volumes, where the reference's own memory would exceed the machine's.
    bool compare_with_reference = true;
    // Give every frame's simulated time a 95% band over the documented guesses' plausible ranges
    // (calibration/uncertainty.h), re-timing the recorded work; stats.json says which guesses matter.
    bool uncertainty = false;
};

struct ScenarioRender {
    nlohmann::json stats;               // what stats.json holds
    std::vector<std::string> lines;     // a summary for a terminal: the machine, the dataset, each frame
    std::vector<std::string> warnings;  // for stderr: outputs that could not be made (a plot without gnuplot)
};

// Renders every frame of `scenario` on `config` into `output` (staged; the caller commits it). Throws
// InputError for what the kernel or the machine cannot do, before any frame runs where it can tell.
ScenarioRender render_scenario(const Scenario& scenario, const MachineConfig& config, StagedOutput& output,
                               const ScenarioRenderOptions& options = {});

}  // namespace pp5
