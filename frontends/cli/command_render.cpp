// `pp5sim render [SCENARIO]`: render every frame of a scenario on a configured machine and write the
// images, stats.json and config.json.
//
// The scenario's kernel (kernels/registry) computes each frame and records its work; the timing
// engine times it on the machine. With the levoy kernel the whole frame runs on the simulated machine:
// the renderers' PPs classify and shade, the GPs cast rays pass after pass of adaptive refinement with
// voxels fetched over the ring. Every frame is also rendered by the floating-point reference renderer,
// and stats.json says how far the two images are apart.
// With the reference kernel the host renderer alone makes the images and simulated time is zero.

#include "frontends/cli/commands.h"
#include "frontends/cli/progress.h"
#include "frontends/image_io.h"
#include "frontends/render_scenario.h"
#include "frontends/staged_output.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

namespace pp5::cli {
namespace {

struct RenderOptions {
    std::string scenario = kDefaultScenario;
    std::string machine = "pxpl5";
    std::vector<std::string> overrides;
    std::string out;
    int threads = 0;  // 0 = every core
    std::string format = "png";
    std::string trace;                   // Chrome trace-event JSON file; empty: none
    std::string trace_window = "0:inf";  // simulated milliseconds
    std::size_t trace_limit = 500000;    // events
    bool pictures = false;
    bool no_reference = false;
    bool uncertainty = false;
};

// "START:END" in simulated milliseconds ("inf" for no end).
std::pair<Tick, Tick> parse_trace_window(const std::string& text) {
    const auto fail = [&](const std::string& why) { throw InputError("--trace-window", "--trace-window", why); };
    const auto colon = text.find(':');
    if (colon == std::string::npos) fail("expected START:END in simulated milliseconds, e.g. 0:50");
    const auto parse_ms = [&](const std::string& part) -> Tick {
        if (part == "inf") return kMaxTick;
        std::size_t used = 0;
        double ms = 0.0;
        try {
            ms = std::stod(part, &used);
        } catch (const std::exception&) {
            fail("'" + part + "' is not a number of milliseconds");
        }
        if (used != part.size() || !std::isfinite(ms) || ms < 0.0 || ms > 1e9)
            fail("'" + part + "' is not a number of milliseconds from 0");
        return static_cast<Tick>(ms * 1e9);
    };
    const Tick start = parse_ms(text.substr(0, colon));
    const Tick end = parse_ms(text.substr(colon + 1));
    if (end <= start) fail("the window ends before it starts");
    return {start, end};
}

using Seconds = std::chrono::duration<double>;

int run_render(const RenderOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    // Read and check every input before any work or output.
    const Scenario scenario = load_scenario(resolve_scenario_file(o.scenario));
    const MachineConfig config = load_run_config(o.machine, o.overrides);
    if (o.threads < 0) throw InputError("--threads", "--threads", "must be 0 (all cores) or more");
    if (o.format != "png" && o.format != "exr") throw InputError("--format", "--format", "must be png or exr");
    if (config.machine_kind() == MachineKind::Uniprocessor) {
        throw InputError(
            resolve_machine_file(o.machine).string(), "machine.kind",
            "a uniprocessor machine is timed from recorded work by `pp5sim fit` and `pp5sim reproduce` (targets "
            "naming it); `render` simulates Pixel-planes 5 machines only");
    }
    const ImageFormat format = o.format == "png" ? ImageFormat::Png : ImageFormat::Exr;
    std::optional<TraceRecorder> trace;
    if (!o.trace.empty()) {
        const auto [from, to] = parse_trace_window(o.trace_window);
        trace.emplace(from, to, o.trace_limit);
    }
    const std::size_t threads =
        o.threads > 0 ? static_cast<std::size_t>(o.threads) : std::max(1u, std::thread::hardware_concurrency());
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);

    StagedOutput output(o.out.empty() ? std::filesystem::path("out") / scenario.name : std::filesystem::path(o.out));
    output.own_folder();  // a rerun with fewer frames leaves none of the last run's behind
    if (trace) check_output_file(o.trace, "--trace");
    Progress progress("render " + scenario.name, scenario.frames.size());
    ScenarioRenderOptions options;
    options.format = format;
    options.trace = trace ? &*trace : nullptr;
    options.lecture_pictures = o.pictures;
    options.compare_with_reference = !o.no_reference;
    options.uncertainty = o.uncertainty;
    options.progress = [&progress](std::size_t done, std::size_t) { progress.update(done); };
    StageProgress stages("render " + scenario.name);
    const ScopedWorkListener listening(stages);
    const ScenarioRender rendered = render_scenario(scenario, config, output, options);
    const double host_seconds = Seconds(std::chrono::steady_clock::now() - started).count();
    // The trace is part of the same commit: the run's files appear together or not at all.
    if (trace) output.add_text_at(o.trace, trace->to_text(), "--trace");
    const auto written = output.commit();
    if (trace) {
        fmt::print(
            "  trace: {} events{} in {}\n", trace->events(),
            trace->dropped() > 0 ? fmt::format(" ({} more past --trace-limit)", trace->dropped()) : std::string(),
            o.trace);
    }

    for (const std::string& line : rendered.lines) fmt::print("{}\n", line);
    for (const std::string& warning : rendered.warnings) fmt::print(stderr, "{}\n", warning);
    fmt::print("  host time {:.2f} s with {} thread{}\n", host_seconds, threads, threads == 1 ? "" : "s");
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

}  // namespace

void add_render_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scenario's frames on a configured machine");
    cmd->add_option("scenario", o->scenario,
                    "Scenario file (TOML) or the name of a shipped one (traces/scenarios/); default: the MR head")
        ->capture_default_str();
    cmd->add_option("--machine", o->machine, "Machine file or preset name")->capture_default_str();
    cmd->add_option("--set", o->overrides, "Override a machine parameter, key=value (repeatable; see `pp5sim params`)");
    cmd->add_option("--out", o->out, "Output directory (default out/<scenario name>)");
    cmd->add_option("--threads", o->threads, "Host threads; 0 uses every core. Results do not depend on it")
        ->capture_default_str();
    cmd->add_option("--format", o->format, "Image format: png or exr")->capture_default_str();
    cmd->add_option(
        "--trace", o->trace,
        "Write a Chrome trace-event JSON file of the run (GPs, renderers, ring messages; open it in Perfetto)");
    cmd->add_option("--trace-window", o->trace_window, "Simulated milliseconds to trace, START:END (END may be inf)")
        ->capture_default_str();
    cmd->add_option("--trace-limit", o->trace_limit, "Most events the trace keeps")
        ->check(whole_number())
        ->capture_default_str();
    cmd->add_flag("--pictures", o->pictures,
                  "Also write each frame's refinement passes as a strip and an animated GIF, and a map of which GP "
                  "cast which tile");
    cmd->add_flag(
        "--no-reference", o->no_reference,
        "Skip the host reference renderer: no PSNR or difference images, and about 55 bytes a voxel less memory "
        "(for big volumes)");
    cmd->add_flag(
        "--uncertainty", o->uncertainty,
        "Give each frame's simulated time a 95% band over the documented guesses' plausible ranges (`pp5sim params`), "
        "by re-timing the recorded work; stats.json names the guesses that matter most");
    cmd->callback([o, &run] { run = [o] { return run_render(*o); }; });
}

}  // namespace pp5::cli
