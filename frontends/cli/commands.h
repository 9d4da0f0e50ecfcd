#pragma once
// The subcommands of `pp5sim`. Each registers its options on the CLI11 app and runs when chosen.

#include <CLI/CLI.hpp>

#include <functional>

namespace pp5::cli {

// For options that count things: digits only, so "-1" is refused rather than wrapped to 2^64 - 1.
inline CLI::Validator whole_number() {
    return CLI::Validator(
        [](std::string& text) {
            return !text.empty() && text.size() <= 18 && text.find_first_not_of("0123456789") == std::string::npos
                       ? std::string()
                       : "\"" + text + "\" is not a whole number from 0";
        },
        "WHOLE NUMBER");
}

// Registers a subcommand; sets `run` to the function that executes it after parsing.
void add_render_command(CLI::App& app, std::function<int()>& run);
void add_params_command(CLI::App& app, std::function<int()>& run);
void add_volume_info_command(CLI::App& app, std::function<int()>& run);
void add_fit_command(CLI::App& app, std::function<int()>& run);
void add_reproduce_command(CLI::App& app, std::function<int()>& run);
void add_host_check_command(CLI::App& app, std::function<int()>& run);
void add_sweep_command(CLI::App& app, std::function<int()>& run);
void add_compare_command(CLI::App& app, std::function<int()>& run);
void add_compare_kernels_command(CLI::App& app, std::function<int()>& run);
void add_scenarios_command(CLI::App& app, std::function<int()>& run);
void add_serve_command(CLI::App& app, std::function<int()>& run);

}  // namespace pp5::cli
