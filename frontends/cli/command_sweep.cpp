// `pp5sim sweep [SWEEP]`: architecture experiments over a grid of machine and kernel parameters.
//
// Points that differ only in timing re-time one recording of each scenario; the rest render. The
// whole sweep writes sweep.csv, sweep.json and a plot per scenario. Under mpirun or as a Slurm array
// task (or with --shard K/N) a process runs every N-th point and writes shard-K-of-N.json; `sweep
// --merge DIR` then joins the shards into exactly what one process would have written. The sweep
// links no MPI library: the launchers' environment says which share is whose, and a Slurm array,
// which has no communicator, needs the same merge step anyway.

#include "frontends/cli/commands.h"
#include "frontends/cli/progress.h"
#include "frontends/staged_output.h"
#include "frontends/staged_plot.h"
#include "frontends/sweep/sweep_run.h"
#include "frontends/sweep/sweep_tables.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"
#include "sim/core/json_input.h"

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

namespace pp5::cli {
namespace {

struct SweepOptions {
    std::string sweep;  // file or shipped name; empty: options only
    std::vector<std::string> scenarios;
    std::string machine;
    std::vector<std::string> overrides;
    std::vector<std::string> vary;
    int frames = -1;  // -1: the file's (or all)
    std::string out;
    int threads = 0;
    std::string shard;
    std::vector<std::string> merge;
    std::string plot_x;
    std::string plot_metric;
    bool uncertainty = false;
};

SweepSpec spec_of(const SweepOptions& o) {
    SweepSpec spec;
    if (!o.sweep.empty()) {
        spec = load_sweep_file(resolve_sweep_file(o.sweep));
    } else {
        spec.file = "--vary";
        spec.name = "sweep";
    }
    // Options add to (or, for the scenarios and machine, replace) the file's.
    if (!o.scenarios.empty()) spec.scenarios = o.scenarios;
    if (spec.scenarios.empty() && o.sweep.empty()) spec.scenarios = {kDefaultScenario};
    if (!o.machine.empty()) spec.machine = o.machine;
    for (const std::string& s : o.overrides) spec.fixed.push_back(s);
    for (const std::string& v : o.vary) spec.axes.push_back(parse_vary_option(v));
    if (o.frames >= 0) spec.frames = o.frames;
    if (!o.plot_x.empty()) spec.plot_x = o.plot_x;
    if (!o.plot_metric.empty()) spec.plot_metric = o.plot_metric;
    if (o.uncertainty) spec.uncertainty = true;
    check_sweep_spec(spec);
    return spec;
}

// sweep.json, sweep.csv and the plots, staged; what a whole sweep and a merge both write.
void stage_whole_sweep(StagedOutput& output, const SweepResult& result, std::vector<std::string>& notes) {
    output.add_text("sweep.json", sweep_to_json(result).dump(1) + "\n");
    output.add_text("sweep.csv", sweep_to_csv(result));
    for (const auto& [name, spec] : sweep_plots(result)) {
        if (auto warning = stage_plot(output, spec, name)) notes.push_back("  " + std::move(*warning));
    }
}

std::vector<std::pair<std::string, nlohmann::json>> read_shards(const std::vector<std::string>& directories) {
    std::vector<std::pair<std::string, nlohmann::json>> shards;
    for (const std::string& d : directories) {
        std::error_code error;
        if (!std::filesystem::is_directory(d, error)) throw InputError(d, "--merge", "is not a folder of shard files");
        std::vector<std::filesystem::path> files;
        for (std::filesystem::directory_iterator it(d, error), end; !error && it != end; it.increment(error)) {
            const std::string name = it->path().filename().string();
            if (std::error_code unreadable;
                name.starts_with("shard-") && name.ends_with(".json") && it->is_regular_file(unreadable))
                files.push_back(it->path());
        }
        if (error) throw InputError(d, "--merge", "cannot be read: " + error.message());
        std::sort(files.begin(), files.end());
        for (const auto& f : files) {
            constexpr std::uintmax_t kMostShardBytes = std::uintmax_t{1} << 30;
            shards.emplace_back(f.string(), read_json_file(f, "shard", kMostShardBytes));
        }
    }
    return shards;
}

int run_sweep_command(const SweepOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    if (o.threads < 0) throw InputError("--threads", "--threads", "must be 0 (all cores) or more");
    const std::size_t threads =
        o.threads > 0 ? static_cast<std::size_t>(o.threads) : std::max(1u, std::thread::hardware_concurrency());
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<std::string> notes;

    if (!o.merge.empty()) {
        if (!o.sweep.empty() || !o.vary.empty() || !o.shard.empty())
            throw InputError("--merge", "--merge", "joins finished shards; give it no sweep, --vary or --shard");
        const SweepResult merged = merge_sweep_shards(read_shards(o.merge));
        StagedOutput output(o.out.empty() ? std::filesystem::path(o.merge.front()) : std::filesystem::path(o.out));
        stage_whole_sweep(output, merged, notes);
        const auto written = output.commit();
        for (const std::string& n : notes) fmt::print("{}\n", n);
        fmt::print("merged {} points; wrote {} files to {}\n", merged.points.size(), written.size(),
                   output.directory().string());
        return 0;
    }

    const SweepSpec spec = spec_of(o);
    const Shard shard = !o.shard.empty() ? parse_shard(o.shard) : shard_from_environment().value_or(Shard{});
    // Checked before any point runs.
    StagedOutput output(o.out.empty() ? std::filesystem::path("out") / "sweeps" / spec.name
                                      : std::filesystem::path(o.out));
    const std::size_t total = plan_sweep(spec).size();
    const std::size_t mine = (total + shard.count - 1 - shard.index) / shard.count;
    Progress progress(shard.count > 1 ? fmt::format("sweep {} (shard {} of {})", spec.name, shard.index, shard.count)
                                      : "sweep " + spec.name,
                      std::max<std::size_t>(mine, 1));
    const SweepResult result = run_sweep(spec, shard, [&](std::size_t done, std::size_t) { progress.update(done); });
    // What is written is what a reader gets back, so a merge of shards writes the same bytes.
    const SweepResult as_written = sweep_from_json(sweep_to_json(result), "sweep");

    if (shard.count > 1) {
        output.add_text(shard_file_name(shard), sweep_to_json(as_written, shard).dump(1) + "\n");
        notes.push_back(fmt::format("  shard {} of {}: join the shards with `pp5sim sweep --merge {}`", shard.index,
                                    shard.count, output.directory().string()));
    } else {
        stage_whole_sweep(output, as_written, notes);
    }
    const auto written = output.commit();
    std::size_t failed = 0;
    for (const SweepPointResult& p : result.points) failed += !p.error.empty();
    fmt::print("sweep {}: {} of {} points{}{}\n", spec.name, result.points.size(), total,
               failed > 0 ? fmt::format(", {} failed (their rows say why)", failed) : std::string(),
               fmt::format("; host time {:.1f} s with {} thread{}",
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), threads,
                           threads == 1 ? "" : "s"));
    if (spec.uncertainty) {
        const double host = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        fmt::print("  bands: {} re-timings, {:.1f} s of the {:.1f} s ({:.0f}%)\n", result.uncertainty_retimings,
                   result.uncertainty_seconds, host, host > 0 ? 100.0 * result.uncertainty_seconds / host : 0.0);
    }
    for (const std::string& n : notes) fmt::print("{}\n", n);
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

}  // namespace

void add_sweep_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<SweepOptions>();
    CLI::App* cmd =
        app.add_subcommand("sweep", "Run a grid of machine and kernel parameters over scenarios: CSV, JSON and plots");
    cmd->add_option("sweep", o->sweep,
                    "Sweep file (TOML) or the name of a shipped one (traces/sweeps/); or use --vary");
    cmd->add_option("--scenario", o->scenarios,
                    "Scenario to sweep (repeatable; replaces the file's; default: the MR head)");
    cmd->add_option("--machine", o->machine, "Machine file or preset name (default: the file's, else pxpl5)");
    cmd->add_option("--set", o->overrides, "Fix a parameter for every point, key=value (repeatable)");
    cmd->add_option("--vary", o->vary, "Vary a parameter, key=v1,v2,... (repeatable: the grid of every combination)");
    cmd->add_option("--frames", o->frames, "Frames of each scenario to run (0: all; default: the file's, else all)")
        ->check(whole_number());
    cmd->add_option("--out", o->out, "Output directory (default out/sweeps/<name>)");
    cmd->add_option("--threads", o->threads, "Host threads; 0 uses every core. Results do not depend on it")
        ->capture_default_str();
    cmd->add_option(
        "--shard", o->shard,
        "Run shard K of N (every N-th point from K); under mpirun or a Slurm array it is taken from the environment");
    cmd->add_option("--merge", o->merge,
                    "Join the shard-K-of-N.json files in these folders into the whole sweep's outputs");
    cmd->add_option("--plot-x", o->plot_x, "The varied parameter the plots put along x (default: the first)");
    cmd->add_option("--plot-metric", o->plot_metric, "The metric the plots show (default: the kernel's first)");
    cmd->add_flag(
        "--uncertainty", o->uncertainty,
        "Add <metric>_low and <metric>_high: each metric's 95% band over the documented guesses' plausible ranges");
    cmd->callback([o, &run] { run = [o] { return run_sweep_command(*o); }; });
}

}  // namespace pp5::cli
