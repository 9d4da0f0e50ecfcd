#pragma once
// What a sweep asks for: scenarios, a machine with fixed overrides, axes of parameter values whose
// every combination is a point (a grid), and explicit extra points. Read from a sweep file (TOML,
// traces/sweeps/, documented in traces/README.md) or built from `--vary key=v1,v2` options.
// Values are kept as the text a --set override takes, so any machine or kernel parameter can vary, and
// so can the kernel itself (kSweepKernelKey).

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace pp5 {

struct SweepAxis {
    std::string key;                  // "gp.count"
    std::vector<std::string> values;  // as --set takes them: "16", "40.0", "work_queue"
};

using SweepAssignment = std::vector<std::pair<std::string, std::string>>;  // key, value

struct SweepSpec {
    std::string name = "sweep";
    std::string description;
    std::string file;                    // where it came from (for errors); "--vary" for options
    std::vector<std::string> scenarios;  // names or paths, as `render` takes them
    std::string machine = "pxpl5";
    std::vector<std::string> fixed;       // "key=value", applied to every point
    int frames = 0;                       // frames of each scenario to run; 0: all
    std::vector<SweepAxis> axes;          // the grid, first axis slowest
    std::vector<SweepAssignment> points;  // explicit points, after the grid
    std::string plot_x;                   // the axis the plots put along x (default: the first)
    std::string plot_metric;              // the metric they show (default: the kernel's first)
    bool uncertainty = false;             // add each metric's band over the documented guesses' ranges
};

// Reads and checks a sweep file: unknown tables or fields, wrong types, unknown parameters, values a
// parameter refuses, empty axes and too many points throw InputError naming the file and the field.
SweepSpec load_sweep_file(const std::filesystem::path& path);
// A sweep file by path, or the name of one shipped in traces/sweeps/.
std::filesystem::path resolve_sweep_file(const std::string& name_or_path);
// Every sweep file shipped (and in $PP5SIM_SWEEPS).
std::vector<std::filesystem::path> shipped_sweep_files();

// "gp.count=8,16,32" as --vary gives it.
SweepAxis parse_vary_option(const std::string& text);

// Checks a spec however it was made (scenarios exist, every key and value is one the machine takes,
// keys appear once); throws InputError naming spec.file and the field.
void check_sweep_spec(const SweepSpec& spec);

// The one key a sweep varies that is not a machine parameter: the kernel that renders each scenario
// (values: registered kernels' names). A point whose kernel cannot render a scenario is a row saying why.
inline constexpr const char* kSweepKernelKey = "kernel";

// The most points a sweep may have: beyond it, it is refused up front.
inline constexpr std::size_t kMaxSweepPoints = 100000;

}  // namespace pp5
