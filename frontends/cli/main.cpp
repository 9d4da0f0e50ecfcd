// pp5sim: the command-line front end of the Pixel-planes 5 volume rendering simulator.

#include "frontends/cli/commands.h"
#include "sim/core/host_memory.h"
#include "sim/core/input_error.h"
#include "sim/core/spelling.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

// Exit codes, the same for every command: bad input (or a usage mistake) is 2, our own fault 1.
constexpr int kBadInput = 2;
constexpr int kInternalError = 1;

// A usage error as one line, with a suggestion when the word given is close to a real one.
std::string usage_error(const CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
    std::string message = e.what();
    std::vector<std::string> commands;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        commands.push_back(sub->get_name());
    const CLI::App* chosen = nullptr;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        if (sub->parsed()) chosen = sub;
    if (chosen == nullptr) {
        // The first word is not a command: say which one it may have meant.
        const std::string first = argc > 1 ? argv[1] : "";
        std::string list;
        for (const std::string& c : commands) list += (list.empty() ? "" : ", ") + c;
        if (first.empty() || first.starts_with("-"))
            return fmt::format("a command is required: {} (pp5sim --help)", list);
        const std::string guess = pp5::closest_name(first, commands);
        return fmt::format("\"{}\" is not a command{}; the commands are {}", first,
                           guess.empty() ? "" : "; did you mean " + guess + "?", list);
    }
    // An option the command does not have: the nearest one it does.
    std::vector<std::string> options;
    for (const CLI::Option* o : chosen->get_options())
        for (const std::string& name : o->get_lnames()) options.push_back("--" + name);
    for (int i = 1; i < argc; ++i) {
        std::string word = argv[i];
        if (!word.starts_with("--")) continue;
        word = word.substr(0, word.find('='));
        if (std::find(options.begin(), options.end(), word) != options.end()) continue;
        const std::string guess = pp5::closest_name(word, options);
        if (!guess.empty())
            return fmt::format("{}: {}; did you mean {}? (pp5sim {} --help)", chosen->get_name(), message, guess,
                               chosen->get_name());
    }
    return fmt::format("{}: {} (pp5sim {} --help)", chosen->get_name(), message, chosen->get_name());
}

}  // namespace

int main(int argc, char** argv) {
    pp5::keep_freed_memory_for_reuse();
    CLI::App app{"pp5sim: a cycle-approximate simulator of the Pixel-planes 5 volume rendering workstation"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("pp5sim ") + PP5SIM_VERSION);
    std::function<int()> run;
    pp5::cli::add_render_command(app, run);
    pp5::cli::add_params_command(app, run);
    pp5::cli::add_volume_info_command(app, run);
    pp5::cli::add_fit_command(app, run);
    pp5::cli::add_reproduce_command(app, run);
    pp5::cli::add_host_check_command(app, run);
    pp5::cli::add_sweep_command(app, run);
    pp5::cli::add_compare_command(app, run);
    pp5::cli::add_compare_kernels_command(app, run);
    pp5::cli::add_scenarios_command(app, run);
    pp5::cli::add_serve_command(app, run);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "pp5sim: error: {}\n", usage_error(app, e, argc, argv));
        return kBadInput;
    }
    // Bad input exits 2 with one line naming file, field and reason; anything else is our fault, 1.
    try {
        return run();
    } catch (const pp5::InputError& e) {
        fmt::print(stderr, "pp5sim: error: {}\n", e.what());
        return kBadInput;
    } catch (const std::bad_alloc&) {
        // A run the up-front checks let through (they count the large allocations an input decides, not all).
        fmt::print(stderr, "pp5sim: error: {}\n", pp5::out_of_memory_message());
        return kBadInput;
    } catch (const std::exception& e) {
        fmt::print(stderr, "pp5sim: internal error: {}\n", e.what());
        return kInternalError;
    }
}
