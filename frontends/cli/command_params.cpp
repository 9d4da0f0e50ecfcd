// `pp5sim params`: the kernels, and every machine and kernel parameter with its value, unit, range, doc
// and provenance.

#include "frontends/cli/commands.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "sim/core/config.h"
#include "sim/machine/machine.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace pp5::cli {
namespace {

struct ParamsOptions {
    std::string machine;
    std::vector<std::string> overrides;
    bool json = false;
};

std::string format_range(const ParamSpec& spec) {
    if (!spec.choices.empty()) return fmt::format("{}", fmt::join(spec.choices, "|"));
    if (!spec.min && !spec.max) return "";
    return fmt::format("[{}, {}]", spec.min.value_or(-INFINITY), spec.max.value_or(INFINITY));
}

int run_params(const ParamsOptions& options) {
    MachineConfig config(run_param_groups());
    if (!options.machine.empty()) config.load_file(resolve_machine_file(options.machine));
    for (const auto& o : options.overrides) config.apply_override(o);
    const nlohmann::json resolved = config.to_json()["parameters"];

    if (options.json) {
        nlohmann::json out = nlohmann::json::array();
        for (const ParamGroup* group : config.groups())
            for (const ParamSpec& spec : group->specs()) {
                const std::string key = group->prefix() + "." + spec.name;
                nlohmann::json def;
                std::visit([&](const auto& v) { def = v; }, spec.default_value);
                out.push_back({{"key", key},
                               {"type", to_string(spec.type)},
                               {"unit", spec.unit},
                               {"default", def},
                               {"value", resolved[key]["value"]},
                               {"origin", resolved[key]["origin"]},
                               {"min", spec.min ? nlohmann::json(*spec.min) : nlohmann::json(nullptr)},
                               {"max", spec.max ? nlohmann::json(*spec.max) : nlohmann::json(nullptr)},
                               {"choices", spec.choices},
                               {"doc", spec.doc},
                               {"provenance", to_string(spec.provenance)},
                               {"source", spec.source},
                               {"plausible", spec.plausible ? nlohmann::json{{"low", spec.plausible->low},
                                                                             {"high", spec.plausible->high},
                                                                             {"why", spec.plausible->why}}
                                                            : nlohmann::json(nullptr)}});
            }
        fmt::print("{}\n", out.dump(2));
        return 0;
    }
    fmt::print("Kernels ([scenario] kernel = \"...\"); each adds its parameter groups below:\n");
    for (const Kernel* kernel : kernels()) {
        std::vector<std::string> prefixes;  // a prefix may hold several groups (voxel_store.*)
        for (const ParamGroup* g : kernel->param_groups())
            if (std::find(prefixes.begin(), prefixes.end(), g->prefix()) == prefixes.end())
                prefixes.push_back(g->prefix());
        std::string groups;
        for (const std::string& prefix : prefixes) groups += (groups.empty() ? "" : ", ") + prefix + ".*";
        fmt::print("  {:<10} {}{}\n", kernel->name(), kernel->description(), groups.empty() ? "" : " [" + groups + "]");
    }
    fmt::print("\n");
    for (const ParamGroup* group : config.groups()) {
        fmt::print("[{}]  {}\n", group->prefix(), group->description());
        for (const ParamSpec& spec : group->specs()) {
            const std::string key = group->prefix() + "." + spec.name;
            const std::string value = resolved[key]["value"].dump();
            const std::string origin = resolved[key]["origin"];
            fmt::print("  {:<34} = {:<10} {:<7} {:<16} ({})\n", key, value, spec.unit, format_range(spec),
                       origin == "default" ? "default" : "from " + origin);
            fmt::print("      {}{}\n      provenance: {}: {}\n", spec.doc,
                       spec.timing_only ? " [timing only: a recorded frame is re-timed, not rendered again]" : "",
                       to_string(spec.provenance), spec.source);
            if (spec.plausible)
                fmt::print("      plausible: [{}, {}]: {}\n", spec.plausible->low, spec.plausible->high,
                           spec.plausible->why);
        }
        fmt::print("\n");
    }
    return 0;
}

}  // namespace

void add_params_command(CLI::App& app, std::function<int()>& run) {
    auto options = std::make_shared<ParamsOptions>();
    CLI::App* cmd =
        app.add_subcommand("params", "List every machine parameter: value, unit, range, doc and provenance");
    cmd->add_option("--machine", options->machine, "Show the values a machine file (or preset name) gives");
    cmd->add_option("--set", options->overrides, "Override a parameter, key=value (repeatable)");
    cmd->add_flag("--json", options->json, "Write the table as JSON");
    cmd->callback([options, &run] { run = [options] { return run_params(*options); }; });
}

}  // namespace pp5::cli
