#pragma once
// The plots `pp5sim reproduce` draws (frontends/cli/command_calibrate.cpp): each target's reported
// figure against its simulated one, and a frame's time against the GP count.

#include "calibration/fit.h"
#include "calibration/timing_model.h"
#include "frontends/plot.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pp5::cli {

// One plot per metric unit of the report's rows (seconds and polygons a second on one axis would say
// nothing about either), named reported_vs_simulated_<unit>.
std::vector<std::pair<std::string, PlotSpec>> reported_vs_simulated(const FitReport& report);

// The frame the GP sweep varies: the first Pixel-planes 5 target timed in seconds sets its scenario,
// frame and machine, and every seconds metric the targets give for that frame is swept.
struct GpSweepFrame {
    const Target* target = nullptr;  // none: the targets time no Pixel-planes 5 frame in seconds
    std::vector<std::string> metrics;
};
GpSweepFrame gp_sweep_frame(const CalibrationModel& model);

// The frame time against the GP count with the report's scales: the plot (with perfect speed-up and
// the reported figures at the machine's own count), its Markdown section and its data.
struct GpSweep {
    PlotSpec plot;
    std::string markdown;
    nlohmann::json data;
};
GpSweep gp_sweep(const CalibrationModel& model, const FitReport& report, const GpSweepFrame& sweep,
                 const std::vector<int>& gp_counts, bool uncalibrated,
                 const std::function<void(const std::string&)>& say);

}  // namespace pp5::cli
