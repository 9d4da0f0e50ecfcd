// `pp5sim compare-kernels [SCENARIO]`: every kernel that runs on the machine renders the scenario on the
// same machine, view, transfer function and lights, and one report says how they differ: pictures,
// PSNR against the oracle, simulated time and where it went, utilisation, ring traffic and backing
// store, and why a kernel that cannot render the scenario does not.

#include "frontends/cli/commands.h"
#include "frontends/cli/progress.h"
#include "frontends/compare_kernels.h"
#include "frontends/image_io.h"
#include "frontends/staged_output.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace pp5::cli {
namespace {

struct CompareKernelsCommandOptions {
    std::string scenario = kDefaultScenario;
    std::string machine = "pxpl5";
    std::vector<std::string> overrides;
    std::string out;
    int threads = 0;
    bool no_reference = false;
};

int run_compare_kernels(const CompareKernelsCommandOptions& o) {
    const Scenario scenario = load_scenario(resolve_scenario_file(o.scenario));
    const MachineConfig config = load_run_config(o.machine, o.overrides);
    if (o.threads < 0) throw InputError("--threads", "--threads", "must be 0 (all cores) or more");
    const std::size_t threads =
        o.threads > 0 ? static_cast<std::size_t>(o.threads) : std::max(1u, std::thread::hardware_concurrency());
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
    StagedOutput output(o.out.empty() ? std::filesystem::path("out") / "compare-kernels" / scenario.name
                                      : std::filesystem::path(o.out));

    CompareKernelsOptions options;
    options.compare_with_reference = !o.no_reference;
    StageProgress stages("compare-kernels " + scenario.name);
    const ScopedWorkListener listening(stages);
    const KernelComparison comparison = compare_kernels(scenario, config, options);

    output.add_text("report.md", to_markdown(comparison));
    output.add_text("report.json", to_json(comparison).dump(1) + "\n");
    bool any = false;
    for (const KernelComparisonRow& row : comparison.rows) {
        if (!row.rendered()) continue;
        output.add_image(row.kernel + ".png", row.picture, ImageFormat::Png);
        any = true;
    }
    if (any) output.add_image("side_by_side.png", side_by_side(comparison), ImageFormat::Png);
    const auto written = output.commit();

    fmt::print("compare-kernels {} on {}:\n", comparison.scenario, comparison.machine);
    for (const KernelComparisonRow& row : comparison.rows) {
        if (!row.rendered()) {
            fmt::print("  {:<8} refused: {}\n", row.kernel, row.refusal);
            continue;
        }
        fmt::print("  {:<8} {:9.3f} ms a frame{}{}\n", row.kernel, 1e3 * row.mean_frame_seconds(),
                   row.psnr_db ? fmt::format(", {:.1f} dB", *row.psnr_db) : std::string(),
                   row.adaptation.empty() ? std::string() : " (" + row.adaptation + ")");
    }
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

}  // namespace

void add_compare_kernels_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<CompareKernelsCommandOptions>();
    CLI::App* cmd = app.add_subcommand(
        "compare-kernels", "Render a scenario with every kernel on one machine and write one report comparing them");
    cmd->add_option("scenario", o->scenario, "Scenario file (TOML) or the name of a shipped one; default: the MR head")
        ->capture_default_str();
    cmd->add_option("--machine", o->machine, "Machine file or preset name")->capture_default_str();
    cmd->add_option("--set", o->overrides, "Override a machine parameter, key=value (repeatable; see `pp5sim params`)");
    cmd->add_option("--out", o->out, "Output directory (default out/compare-kernels/<scenario name>)");
    cmd->add_option("--threads", o->threads, "Host threads; 0 uses every core. Results do not depend on it")
        ->capture_default_str();
    cmd->add_flag("--no-reference", o->no_reference, "Skip the host reference renderer (no PSNR): for big volumes");
    cmd->callback([o, &run] { run = [o] { return run_compare_kernels(*o); }; });
}

}  // namespace pp5::cli
