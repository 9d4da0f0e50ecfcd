#pragma once
// The subcommands of `pp5sim`. Each registers its options on the CLI11 app and runs when chosen.

#include <CLI/CLI.hpp>

#include <functional>

namespace pp5::cli {

// Registers a subcommand; sets `run` to the function that executes it after parsing.
void add_render_command(CLI::App& app, std::function<int()>& run);
void add_params_command(CLI::App& app, std::function<int()>& run);
void add_volume_info_command(CLI::App& app, std::function<int()>& run);
void add_fit_command(CLI::App& app, std::function<int()>& run);
void add_reproduce_command(CLI::App& app, std::function<int()>& run);
void add_host_check_command(CLI::App& app, std::function<int()>& run);
void add_sweep_command(CLI::App& app, std::function<int()>& run);
void add_compare_command(CLI::App& app, std::function<int()>& run);

}  // namespace pp5::cli
