#pragma once
// Two runs' statistics side by side: every number in two stats.json files, matched by where it sits
// ("components/gp[3]/busy_time", "frames/0/simulated_seconds"), with its unit where the file gives
// one, and how it changed. Host timings (keys named host_seconds) differ from run to run on any
// computer and are left out unless asked for.

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pp5 {

struct StatDifference {
    std::string path;
    std::string unit;              // "" when the file gives none
    std::optional<double> before;  // none: only in the second
    std::optional<double> after;   // none: only in the first
    double absolute() const { return before && after ? *after - *before : 0.0; }
    // (after - before) / |before|; infinite when before is 0 and after is not, or one side is missing.
    double relative() const;
};

struct StatsComparison {
    std::vector<StatDifference> differences;  // in both: by |relative change|, largest first; then in one only
    std::size_t compared = 0;                 // numbers found in both
    std::size_t beyond_tolerance = 0;         // differences whose |relative change| exceeds the tolerance
};

struct CompareOptions {
    double tolerance = 0.0;     // relative; a change within it is not beyond it
    bool include_host = false;  // compare host_seconds too
};

// Throws InputError naming `file` unless `json` is a run's stats.json as `pp5sim render` writes it:
// an object with components, frames and a summary that gives the scenario, the kernel and each
// frame's simulated time. A sweep's results, or any other JSON, is refused saying what it is.
void check_run_stats(const nlohmann::json& json, const std::string& file);

StatsComparison compare_stats(const nlohmann::json& before, const nlohmann::json& after, const CompareOptions& options);

}  // namespace pp5
