// `pp5sim scenarios`: what can be run without writing a file: the shipped scenarios (with their
// kernels), the shipped sweeps, and the Debian-packaged volumes a scenario can name, with whether each
// is installed here and, if not, the package that brings it.

#include "frontends/cli/commands.h"
#include "frontends/sweep/sweep_spec.h"
#include "scene/scenario/scenario.h"
#include "scene/volume/datasets.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <filesystem>

namespace pp5::cli {
namespace {

int run_scenarios() {
    fmt::print("Scenarios (pp5sim render NAME):\n");
    for (const auto& path : shipped_scenario_files()) {
        try {
            const Scenario s = load_scenario(path);
            fmt::print("  {:<20} {:<10} {}\n", path.stem().string(), s.kernel, s.description);
        } catch (const InputError& e) {
            fmt::print("  {:<20} {:<10} cannot be read: {}\n", path.stem().string(), "-", e.what());
        }
    }
    fmt::print("\nSweeps (pp5sim sweep NAME):\n");
    for (const auto& path : shipped_sweep_files()) {
        try {
            const SweepSpec s = load_sweep_file(path);
            fmt::print("  {:<20} {}\n", path.stem().string(), s.description);
        } catch (const InputError& e) {
            fmt::print("  {:<20} cannot be read: {}\n", path.stem().string(), e.what());
        }
    }
    fmt::print("\nPackaged volumes (a scenario's dataset.packaged = NAME):\n");
    for (const PackagedDataset& d : packaged_datasets()) {
        std::error_code error;
        const bool here = std::filesystem::is_regular_file(d.path, error);
        fmt::print("  {:<12} {:<40} {}\n", d.name, here ? "installed" : "missing: apt-get install " + d.package,
                   d.description);
    }
    return 0;
}

}  // namespace

void add_scenarios_command(CLI::App& app, std::function<int()>& run) {
    CLI::App* cmd = app.add_subcommand(
        "scenarios", "List the shipped scenarios and sweeps, and the packaged volumes (installed or not)");
    cmd->callback([&run] { run = [] { return run_scenarios(); }; });
}

}  // namespace pp5::cli
