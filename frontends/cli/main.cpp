// pp5sim: the command-line front end of the Pixel-planes 5 volume rendering simulator.

#include "frontends/cli/commands.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"pp5sim: a cycle-approximate simulator of the Pixel-planes 5 volume rendering workstation"};
    app.require_subcommand(1);
    std::function<int()> run;
    pp5::cli::add_render_command(app, run);
    pp5::cli::add_params_command(app, run);
    pp5::cli::add_volume_info_command(app, run);
    pp5::cli::add_fit_command(app, run);
    pp5::cli::add_reproduce_command(app, run);
    pp5::cli::add_host_check_command(app, run);
    pp5::cli::add_sweep_command(app, run);
    pp5::cli::add_compare_command(app, run);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    // Bad input exits 2 with one line naming file, field and reason; anything else is our fault, 1.
    try {
        return run();
    } catch (const pp5::InputError& e) {
        fmt::print(stderr, "pp5sim: error: {}\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        fmt::print(stderr, "pp5sim: internal error: {}\n", e.what());
        return 1;
    }
}
