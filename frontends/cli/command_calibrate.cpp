// `pp5sim fit` and `pp5sim reproduce`: calibrate the timing model against a target file, and reproduce
// the papers' table with the calibrated machines (calibration/fit.h).
//
// fit:       the fitted machine files (<machine>-fitted.toml), fit.md and fit.json.
// reproduce: the fit's files, then reproduction.md and reproduction.json (one row per target), the
//            figure-like images, and plots: reported against simulated, and simulated frame time
//            against the number of GPs for a crude and a refined frame.

#include "calibration/fit.h"
#include "calibration/host_check.h"
#include "calibration/residuals.h"
#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "calibration/uncertainty_report.h"
#include "frontends/cli/commands.h"
#include "frontends/cli/reproduction_plots.h"
#include "frontends/staged_output.h"
#include "frontends/staged_plot.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <thread>

namespace pp5::cli {
namespace {

struct CalibrateOptions {
    std::string targets = kDefaultTargets;
    std::string out;
    int threads = 0;
    bool leave_one_out = true;
    bool workload_step = true;
    bool uncalibrated = false;                                // reproduce only: skip the fit
    std::vector<int> gp_counts{1, 2, 4, 8, 16, 32, 64, 128};  // reproduce only
    bool host_check = true;                                   // reproduce only
    int repeats = 3;                                          // host check: best of
};

void add_common_options(CLI::App* cmd, CalibrateOptions& o) {
    cmd->add_option("--targets", o.targets, "Target file (TOML) or the name of a shipped one (traces/calibration/)")
        ->capture_default_str();
    cmd->add_option("--out", o.out, "Output directory");
    cmd->add_option("--threads", o.threads,
                    "Host threads for rendering the scenarios once; 0 uses every core. Results do not depend on it");
    cmd->add_flag("!--no-leave-one-out", o.leave_one_out, "Skip refitting without each fitted target");
    cmd->add_flag("!--no-workload-step", o.workload_step,
                  "Keep the machine files' values of the target file's [[workload]] parameters instead of identifying "
                  "them first");
}

void say(const std::string& line) { fmt::print(stderr, "  {}\n", line); }

struct Prepared {
    std::vector<IdentifiedWorkload> workload;
    std::unique_ptr<CalibrationModel> model;
};

// Reads the targets, identifies their workload parameters, and renders their scenarios once.
Prepared prepare(const CalibrateOptions& o, std::optional<tbb::global_control>& parallelism) {
    if (o.threads < 0) throw InputError("--threads", "--threads", "must be 0 (all cores) or more");
    const TargetSet targets = load_targets(resolve_targets_file(o.targets));
    const std::size_t threads =
        o.threads > 0 ? static_cast<std::size_t>(o.threads) : std::max(1u, std::thread::hardware_concurrency());
    parallelism.emplace(tbb::global_control::max_allowed_parallelism, threads);
    Prepared prepared;
    if (o.workload_step && !targets.workload.empty()) {
        fmt::print(stderr, "pp5sim: identifying {} workload parameter(s) of {} from measured rows\n",
                   targets.workload.size(), targets.file.string());
        WorkloadOptions options;
        options.progress = say;
        prepared.workload = identify_workload(targets, options);
    }
    fmt::print(stderr, "pp5sim: {} targets from {}; rendering their scenarios once\n", targets.targets.size(),
               targets.file.string());
    prepared.model =
        std::make_unique<CalibrationModel>(targets, std::nullopt, workload_settings(prepared.workload), say);
    return prepared;
}

FitReport fit(const Prepared& prepared, const CalibrateOptions& o) {
    FitOptions options;
    options.leave_one_out = o.leave_one_out;
    options.progress = say;
    FitReport report = fit_targets(*prepared.model, options);
    report.workload = prepared.workload;
    return report;
}

std::set<std::string> machines_of(const CalibrationModel& model) {
    std::set<std::string> machines;
    for (const Target& t : model.targets().targets)
        if (!t.is_formula()) machines.insert(t.machine);
    return machines;
}

void stage_fit(StagedOutput& output, const CalibrationModel& model, const FitReport& report) {
    output.add_text("fit.md", report.to_markdown());
    output.add_text("fit.json", report.to_json().dump(2) + "\n");
    for (const std::string& machine : machines_of(model)) {
        const std::string name = std::filesystem::path(machine).stem().string() + "-fitted.toml";
        output.add_text(name, fitted_machine_file(model, report, machine));
    }
}

void print_summary(const FitReport& report) {
    for (const FittedParameter& p : report.parameters) {
        if (!p.free) continue;
        fmt::print("  {} {} = {:.4g} +/- {:.2g}{}\n", p.machine, p.key, p.value, p.standard_error,
                   p.at_bound ? " (at bound)" : "");
    }
    for (const RowGroup group : kRowGroups) {
        const ErrorSummary s = report.summary(group);
        if (s.count == 0) continue;
        fmt::print("  {}: {} targets, mean abs. error {:.1f}%, max {:.1f}%, {} within 10%, {} within 25%\n",
                   describe(group), s.count, 100.0 * s.mean_absolute_error, 100.0 * s.max_absolute_error, s.within_10,
                   s.within_25);
    }
}

// Where a command writes: --out, or out/<command>; checked before any work.
std::filesystem::path output_folder(const CalibrateOptions& o, const char* command) {
    const std::filesystem::path folder =
        o.out.empty() ? std::filesystem::path("out") / command : std::filesystem::path(o.out);
    check_output_folder(folder, "--out");
    return folder;
}

bool has_fitted_rows(const TargetSet& targets) {
    return std::any_of(targets.targets.begin(), targets.targets.end(),
                       [](const Target& t) { return t.fitted() && !t.is_formula(); });
}

int run_fit(const CalibrateOptions& o) {
    const std::filesystem::path folder = output_folder(o, "fit");
    // Refused before any scenario is rendered.
    const std::filesystem::path targets_file = resolve_targets_file(o.targets);
    if (!has_fitted_rows(load_targets(targets_file)))
        throw InputError(targets_file.string(), "targets",
                         "no row is to be fitted (every one is held out, a check, by construction or a comparison): "
                         "nothing to fit; set use = \"fit\" on "
                         "some, or compare them with `pp5sim reproduce --uncalibrated`");
    std::optional<tbb::global_control> parallelism;
    const Prepared prepared = prepare(o, parallelism);
    const auto& model = prepared.model;
    const FitReport report = fit(prepared, o);
    StagedOutput output(folder);
    stage_fit(output, *model, report);
    const auto written = output.commit();
    fmt::print("pp5sim fit: {} ({:.0f} s)\n", model->targets().name, report.host_seconds);
    print_summary(report);
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

// Without gnuplot a plot keeps its data and script, and the user hears why its picture is missing.
void stage_plot_or_warn(StagedOutput& output, const PlotSpec& spec, const std::string& name) {
    if (const auto warning = stage_plot(output, spec, name)) fmt::print(stderr, "{}\n", *warning);
}

HostCheckReport host_check(const CalibrateOptions& o) {
    if (o.repeats < 1) throw InputError("--repeats", "--repeats", "must be at least 1");
    HostCheckOptions options;
    options.repeats = o.repeats;
    options.progress = say;
    return run_host_check(load_run_config("host", {}), options);
}

void stage_host_check(StagedOutput& output, const HostCheckReport& report) {
    output.add_text("host_check.md", report.to_markdown());
    output.add_text("host_check.json", report.to_json().dump(2) + "\n");
    PlotSpec spec;
    spec.title = "The model against this machine: reference renderer, one thread";
    spec.x_label = "measured (s)";
    spec.y_label = "predicted (s)";
    spec.log_x = spec.log_y = true;
    PlotSeries fitted{"fitted cases", {}, {}, "points pt 7 ps 1.4 lc rgb '#1f77b4'", {}, {}};
    PlotSeries held{"held-out cases", {}, {}, "points pt 5 ps 1.4 lc rgb '#d62728'", {}, {}};
    for (const HostCase& c : report.cases) {
        PlotSeries& series = c.fitted ? fitted : held;
        series.x.push_back(c.measured_seconds);
        series.y.push_back(c.predicted_seconds);
    }
    spec.series = {fitted, held};
    spec.extra_plots = {"x title 'predicted = measured' lw 2 lc rgb 'black'",
                        "1.2*x title '+/- 20%' dt 2 lc rgb 'gray'", "x/1.2 notitle dt 2 lc rgb 'gray'"};
    stage_plot_or_warn(output, spec, "host_check");
}

int run_host_check_command(const CalibrateOptions& o) {
    const std::filesystem::path folder = output_folder(o, "host-check");
    const HostCheckReport report = host_check(o);
    StagedOutput output(folder);
    stage_host_check(output, report);
    const auto written = output.commit();
    fmt::print("pp5sim host-check: median absolute error {:.1f}% fitted, {:.1f}% held out (max {:.1f}%)\n",
               100 * report.median_fitted_error, 100 * report.median_held_out_error, 100 * report.max_held_out_error);
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

// The fitted (or, uncalibrated, the evaluated) report the reproduction is made of; a fit is staged.
FitReport reproduction_report(const Prepared& prepared, const CalibrateOptions& o, bool uncalibrated,
                              StagedOutput& output) {
    const auto& model = prepared.model;
    if (!uncalibrated) {
        FitReport report = fit(prepared, o);
        stage_fit(output, *model, report);
        return report;
    }
    FitReport report = evaluate_targets(*model, {});
    report.workload = prepared.workload;
    for (TargetResult& r : report.results)
        if (!r.target.is_formula()) r.uncalibrated = r.simulated;  // the column the guesses' intervals go in
    return report;
}

// The table: every target with the (fitted) machines, why each row that misses does, and what holds
// across the guesses' plausible ranges. Returns the Markdown so far.
std::string stage_reproduction_table(const CalibrationModel& model, FitReport& report, bool uncalibrated,
                                     StagedOutput& output) {
    say("explaining the rows more than 10% off (re-timing each machine with every timing parameter moved)");
    const std::vector<ResidualAccount> residuals = explain_residuals(model, report);
    say("re-timing with every documented guess at either end of its plausible range");
    add_plausible_bands(model, report);
    const std::vector<Conclusion> conclusions = check_conclusions(model, report);
    const nlohmann::json table = report.to_json();
    output.add_text("reproduction.json", nlohmann::json{{"targets", report.targets_name},
                                                        {"calibrated", !uncalibrated},
                                                        {"rows", table["rows"]},
                                                        {"summary", table["summary"]},
                                                        {"degrees_of_freedom", table["degrees_of_freedom"]},
                                                        {"residuals", residuals_json(residuals)},
                                                        {"conclusions", conclusions_json(conclusions)}}
                                                 .dump(2) +
                                             "\n");
    return report.to_markdown() + residuals_markdown(residuals) + conclusions_markdown(conclusions);
}

// The target file's [[figures]]: figure-like images from the recorded frames (what is computed does
// not depend on the machine's timing), each with the rows that time it. Returns how many.
int stage_figures(const CalibrationModel& model, const FitReport& report, StagedOutput& output, std::string& markdown) {
    int images = 0;
    if (!model.targets().figures.empty())
        markdown += "\n## Figures\n\nEach picture is a recorded frame, with the rows that time it.\n";
    for (const Figure& f : model.targets().figures) {
        const RecordedFrame& frame = model.recording(f.scenario).frames()[static_cast<std::size_t>(f.frame)];
        output.add_image("images/" + f.name + ".png", f.final ? frame.refined_image : frame.crude_image,
                         ImageFormat::Png);
        ++images;
        markdown +=
            fmt::format("\n![{0}](images/{0}.png)\n\n*{0}*: `{1}` frame {2} ({3}), {4}.", f.name, f.scenario, f.frame,
                        frame.label, f.final ? "fully refined" : "its first pass only (the crude picture)");
        for (const TargetResult& r : report.results)
            if (!r.target.is_formula() && r.target.scenario == f.scenario && r.target.frame == f.frame)
                markdown += fmt::format(" `{}`: {} {} reported, {:.4g} simulated ({:+.1f}%).", r.target.id,
                                        r.target.reported, r.target.unit, r.simulated, 100.0 * r.relative_error);
        markdown += "\n";
    }
    return images;
}

// One plot per metric unit of reported against simulated. Returns the plots' file names.
std::string stage_reported_plots(const FitReport& report, StagedOutput& output, std::string& markdown) {
    std::string plot_names;
    markdown +=
        "\n## Reported against simulated\n\nOne plot per metric unit, each point with its 95% interval; grey points "
        "are the uncalibrated values, their bars the documented guesses' plausible ranges.\n";
    for (const auto& [name, spec] : reported_vs_simulated(report)) {
        stage_plot_or_warn(output, spec, name);
        plot_names += name + ".png, ";
        markdown += fmt::format("\n![{0}]({0}.png)\n", name);
    }
    return plot_names;
}

int run_reproduce(const CalibrateOptions& o) {
    if (o.gp_counts.empty()) throw InputError("--gp-counts", "--gp-counts", "needs at least one GP count");
    for (const int n : o.gp_counts)
        if (n < 1 || n > 1024)
            throw InputError("--gp-counts", "--gp-counts", fmt::format("{} is not a GP count from 1 to 1024", n));
    const std::filesystem::path folder = output_folder(o, "reproduce");
    std::optional<tbb::global_control> parallelism;
    const Prepared prepared = prepare(o, parallelism);
    const CalibrationModel& model = *prepared.model;
    // With no row to fit (formula rows, say) there is nothing to calibrate: the table is the model's own.
    const bool uncalibrated = o.uncalibrated || !has_fitted_rows(model.targets());
    StagedOutput output(folder);
    FitReport report = reproduction_report(prepared, o, uncalibrated, output);
    std::string markdown = stage_reproduction_table(model, report, uncalibrated, output);
    const int images = stage_figures(model, report, output, markdown);
    const std::string plot_names = stage_reported_plots(report, output, markdown);
    const GpSweepFrame sweep = gp_sweep_frame(model);
    if (sweep.target) {
        GpSweep g = gp_sweep(model, report, sweep, o.gp_counts, uncalibrated, say);
        stage_plot_or_warn(output, g.plot, "frame_time_vs_gps");
        markdown += g.markdown;
        output.add_text("frame_time_vs_gps.json", g.data.dump(2) + "\n");
    }
    std::optional<HostCheckReport> host;
    if (o.host_check) {
        host = host_check(o);
        stage_host_check(output, *host);
        markdown += fmt::format(
            "\n## Host check\n\nThe same timing model against this computer's measured reference-renderer times "
            "(host_check.md): median absolute error {:.1f}% on the fitted half, {:.1f}% on the held-out half.\n\n"
            "![host check](host_check.png)\n",
            100 * host->median_fitted_error, 100 * host->median_held_out_error);
    }
    output.add_text("reproduction.md", markdown);
    const auto written = output.commit();
    fmt::print("pp5sim reproduce: {} ({})\n", model.targets().name, uncalibrated ? "uncalibrated" : "calibrated");
    if (host) {
        fmt::print("  host check: median absolute error {:.1f}% fitted, {:.1f}% held out\n",
                   100 * host->median_fitted_error, 100 * host->median_held_out_error);
    }
    print_summary(report);
    fmt::print("  {} images; plots {}{}\n", images, plot_names, sweep.target ? "frame_time_vs_gps.png" : "");
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

}  // namespace

void add_fit_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<CalibrateOptions>();
    CLI::App* cmd = app.add_subcommand(
        "fit",
        "Fit the timing model's scale factors to a target file with Ceres; write fitted machine files and a report");
    add_common_options(cmd, *o);
    cmd->callback([o, &run] { run = [o] { return run_fit(*o); }; });
}

void add_reproduce_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<CalibrateOptions>();
    CLI::App* cmd = app.add_subcommand(
        "reproduce", "Fit, then reproduce every target: table (Markdown, JSON), figure images and plots");
    add_common_options(cmd, *o);
    cmd->add_flag("--uncalibrated", o->uncalibrated, "Skip the fit: the machines' own files as they are");
    cmd->add_option("--gp-counts", o->gp_counts, "GP counts for the frame-time sweep")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_flag("!--no-host-check", o->host_check, "Skip the check against this machine (see `pp5sim host-check`)");
    cmd->add_option("--repeats", o->repeats, "Host check: timed runs per case, the best kept")->capture_default_str();
    cmd->callback([o, &run] { run = [o] { return run_reproduce(*o); }; });
}

void add_host_check_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<CalibrateOptions>();
    CLI::App* cmd = app.add_subcommand(
        "host-check", "Fit the host preset to measured reference-renderer timings on half the cases; predict the rest");
    cmd->add_option("--out", o->out, "Output directory");
    cmd->add_option("--repeats", o->repeats, "Timed runs per case, the best kept")->capture_default_str();
    cmd->callback([o, &run] { run = [o] { return run_host_check_command(*o); }; });
}

}  // namespace pp5::cli
