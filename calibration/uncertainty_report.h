#pragma once
// What the reproduction report says about the documented guesses (calibration/uncertainty.h): each
// row's uncalibrated value with its 95% band over the guesses' plausible ranges (so a reader sees
// whether the paper's figure is within what the guesses allow), and conclusions checked across the
// whole range: the claim re-timed with every guess at the end of its range that works against it.

#include "calibration/fit.h"
#include "calibration/timing_model.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pp5 {

// Sets every simulated row's uncalibrated band (TargetResult::plausible_low/_high): its machine as the
// machine file gives it, every guess spread over its plausible range.
void add_plausible_bands(const CalibrationModel& model, FitReport& report);

struct Conclusion {
    std::string claim;
    std::string scenario;
    std::string machine;
    std::string figure;       // what is measured, and the threshold the claim needs
    double on_machine = 0.0;  // the figure as the machine is configured
    double at_worst = 0.0;    // re-timed with every guess at the end that works against the claim
    bool holds = false;
    std::vector<std::string> against;  // the guesses that work against it most, "key = value"
};

// The claims an architect reads off a Pixel-planes 5 run, checked on each multicomputer the rows name
// (its fitted scales applied) with the first scenario it times: the ring is never the bottleneck;
// doubling the GPs from 32 to 64 speeds every frame up.
std::vector<Conclusion> check_conclusions(const CalibrationModel& model, const FitReport& report);

std::string conclusions_markdown(const std::vector<Conclusion>& conclusions);
nlohmann::json conclusions_json(const std::vector<Conclusion>& conclusions);

}  // namespace pp5
