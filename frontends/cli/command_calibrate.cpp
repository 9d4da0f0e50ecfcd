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

// The plots of reported against simulated values, one per metric unit: seconds and polygons a second
// on one axis would say nothing about either. Named reported_vs_simulated_<unit>.
std::vector<std::pair<std::string, PlotSpec>> reported_vs_simulated(const FitReport& report) {
    std::vector<std::pair<std::string, PlotSpec>> plots;
    for (const auto& [unit, summary] : report.by_unit()) {
        PlotSpec spec;
        std::string slug = unit == "s" ? "seconds" : unit == "1/s" ? "per_second" : unit;
        std::replace_if(
            slug.begin(), slug.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
        spec.title = fmt::format("Reported against simulated, {} ({}: {} of {} within 25%)",
                                 unit == "s" ? "seconds" : unit, report.targets_name, summary.within_25, summary.count);
        spec.x_label = "reported (" + unit + ")";
        spec.y_label = "simulated (" + unit + ")";
        spec.log_x = spec.log_y = true;
        // Each point with its 95% interval as an error bar: the fit's for the calibrated values, the
        // documented guesses' for the uncalibrated ones (a point without one gets a bar of no length).
        PlotSeries fitted{"fitted targets (and the workload step's)", {}, {},
                          "yerrorbars pt 7 ps 1.4 lc rgb '#1f77b4'",  {}, {}};
        PlotSeries held{"predicted targets", {}, {}, "yerrorbars pt 5 ps 1.4 lc rgb '#d62728'", {}, {}};
        PlotSeries uncalibrated{"uncalibrated (documented costs and their plausible ranges)",
                                {},
                                {},
                                "yerrorbars pt 6 ps 1.2 lc rgb 'gray'",
                                {},
                                {}};
        const auto add = [](PlotSeries& series, double x, double y, std::optional<double> low,
                            std::optional<double> high) {
            series.x.push_back(x);
            series.y.push_back(y);
            series.y_low.push_back(low.value_or(y));
            series.y_high.push_back(high.value_or(y));
        };
        for (const TargetResult& r : report.results) {
            const RowGroup group = report.group_of(r.target);
            if (r.target.unit != unit ||
                (group != RowGroup::Fitted && group != RowGroup::Workload && group != RowGroup::Predicted))
                continue;
            add(group == RowGroup::Predicted ? held : fitted, r.target.reported, r.simulated, r.low, r.high);
            if (r.uncalibrated)
                add(uncalibrated, r.target.reported, *r.uncalibrated, r.plausible_low, r.plausible_high);
        }
        for (const PlotSeries& s : {fitted, held, uncalibrated})
            if (!s.x.empty()) spec.series.push_back(s);
        spec.extra_plots = {"x title 'simulated = reported' lw 2 lc rgb 'black'",
                            "1.25*x title '+/- 25%' dt 2 lc rgb 'gray'", "0.8*x notitle dt 2 lc rgb 'gray'"};
        plots.emplace_back("reported_vs_simulated_" + slug, std::move(spec));
    }
    return plots;
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

int run_reproduce(const CalibrateOptions& o) {
    if (o.gp_counts.empty()) throw InputError("--gp-counts", "--gp-counts", "needs at least one GP count");
    for (const int n : o.gp_counts)
        if (n < 1 || n > 1024)
            throw InputError("--gp-counts", "--gp-counts", fmt::format("{} is not a GP count from 1 to 1024", n));
    const std::filesystem::path folder = output_folder(o, "reproduce");
    std::optional<tbb::global_control> parallelism;
    const Prepared prepared = prepare(o, parallelism);
    const auto& model = prepared.model;
    // With no row to fit (formula rows, say) there is nothing to calibrate: the table is the model's own.
    const bool uncalibrated = o.uncalibrated || !has_fitted_rows(model->targets());
    StagedOutput output(folder);
    FitReport report;
    if (uncalibrated) {
        report = evaluate_targets(*model, {});
        report.workload = prepared.workload;
        for (TargetResult& r : report.results)
            if (!r.target.is_formula()) r.uncalibrated = r.simulated;  // the column the guesses' intervals go in
    } else {
        report = fit(prepared, o);
        stage_fit(output, *model, report);
    }

    // The table: every target with the (fitted) machines, and why each row that misses does.
    say("explaining the rows more than 10% off (re-timing each machine with every timing parameter moved)");
    const std::vector<ResidualAccount> residuals = explain_residuals(*model, report);
    say("re-timing with every documented guess at either end of its plausible range");
    add_plausible_bands(*model, report);
    const std::vector<Conclusion> conclusions = check_conclusions(*model, report);
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
    std::string markdown = report.to_markdown() + residuals_markdown(residuals) + conclusions_markdown(conclusions);

    // Figure-like images from the recorded frames (what is computed does not depend on the machine's timing).
    // The target file's [[figures]].
    int images = 0;
    if (!model->targets().figures.empty())
        markdown += "\n## Figures\n\nEach picture is a recorded frame, with the rows that time it.\n";
    for (const Figure& f : model->targets().figures) {
        const RecordedFrame& frame = model->recording(f.scenario).frames()[static_cast<std::size_t>(f.frame)];
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

    // Plots.
    std::string plot_names;
    markdown +=
        "\n## Reported against simulated\n\nOne plot per metric unit, each point with its 95% interval; grey points "
        "are the uncalibrated values, their bars the documented guesses' plausible ranges.\n";
    for (const auto& [name, spec] : reported_vs_simulated(report)) {
        stage_plot_or_warn(output, spec, name);
        plot_names += name + ".png, ";
        markdown += fmt::format("\n![{0}]({0}.png)\n", name);
    }
    // The first Pixel-planes 5 target timed in seconds sets the scenario, frame and machine; every
    // seconds metric the targets give for that frame is swept.
    const Target* scaling = nullptr;
    for (const Target& t : model->targets().targets)
        if (!scaling && !t.is_formula() && model->base_config(t.machine).machine_kind() == MachineKind::Multicomputer &&
            t.unit == "s")
            scaling = &t;
    std::vector<std::string> swept;
    if (scaling)
        for (const Target& t : model->targets().targets)
            if (t.scenario == scaling->scenario && t.frame == scaling->frame && t.machine == scaling->machine &&
                t.unit == "s" && std::find(swept.begin(), swept.end(), t.metric) == swept.end())
                swept.push_back(t.metric);
    nlohmann::json sweep = nlohmann::json::array();
    if (scaling) {
        PlotSpec spec;
        spec.title = fmt::format("Frame time against GP count ({}, frame {}, {})", scaling->scenario, scaling->frame,
                                 uncalibrated ? "uncalibrated" : "calibrated");
        spec.x_label = "graphics processors";
        spec.y_label = "simulated frame time (s)";
        spec.log_x = spec.log_y = true;
        const int most = *std::max_element(o.gp_counts.begin(), o.gp_counts.end());
        const int fewest = *std::min_element(o.gp_counts.begin(), o.gp_counts.end());
        spec.extra_commands = {"set xtics (1,2,4,8,16,32,64,128,256,512,1024)",
                               fmt::format("set xrange [{}:{}]", 0.8 * fewest, 1.25 * most)};
        std::vector<PlotSeries> series;
        for (std::size_t m = 0; m < swept.size(); ++m) {
            std::string title = swept[m];  // gnuplot would read an underscore as a subscript
            std::replace(title.begin(), title.end(), '_', ' ');
            series.push_back(PlotSeries{
                title, {}, {}, fmt::format("linespoints pt {} lw 2", 7 - 2 * static_cast<int>(m % 3)), {}, {}});
        }
        const CalibrationScales scales = report.scales(scaling->machine);
        for (const int n : o.gp_counts) {
            say(fmt::format("GP sweep: {} GPs", n));
            MachineConfig config = model->machine_config(scaling->machine, scales);
            config.set("gp.count", static_cast<std::int64_t>(n), "--gp-counts");
            const RecordedScenario& recording = model->recording(scaling->scenario);
            const auto frame = static_cast<std::size_t>(scaling->frame);
            const FrameTiming timing = recording.time_on(config, frame + 1)[frame];
            nlohmann::json point = {{"gps", n}};
            for (std::size_t m = 0; m < swept.size(); ++m) {
                const double seconds = recording.metric(swept[m], frame, timing);
                series[m].x.push_back(n);
                series[m].y.push_back(seconds);
                point[swept[m]] = seconds;
            }
            sweep.push_back(point);
        }
        // Perfect speed-up of the last metric from the fewest GPs, for comparison.
        const PlotSeries& last = series.back();
        PlotSeries ideal{last.title + ", perfect speed-up", {}, {}, "lines dt 2 lc rgb 'gray'", {}, {}};
        for (std::size_t i = 0; i < last.x.size(); ++i) {
            ideal.x.push_back(last.x[i]);
            ideal.y.push_back(last.y.front() * last.x.front() / last.x[i]);
        }
        spec.series = series;
        spec.series.push_back(ideal);
        // The reported figures for the machine's GP count, where the frame's targets give them.
        for (const Target& t : model->targets().targets) {
            if (t.scenario != scaling->scenario || t.frame != scaling->frame || t.machine != scaling->machine) continue;
            if (std::find(swept.begin(), swept.end(), t.metric) == swept.end()) continue;
            const double gps = static_cast<double>(model->base_config(t.machine).integer("gp.count"));
            spec.series.push_back(PlotSeries{"reported: " + t.id, {gps}, {t.reported}, "points pt 9 ps 2.5", {}, {}});
        }
        stage_plot_or_warn(output, spec, "frame_time_vs_gps");
        markdown += fmt::format(
            "\n## Frame time against GP count\n\n![frame time against GP count](frame_time_vs_gps.png)\n\n`{}` frame "
            "{} on {} "
            "with the {} scales, the GP count varied (data: frame_time_vs_gps.json).\n\n| GPs |",
            scaling->scenario, scaling->frame, scaling->machine, uncalibrated ? "uncalibrated" : "fitted");
        for (const std::string& m : swept) markdown += " " + m + " (s) |";
        markdown += "\n|---|";
        for (std::size_t m = 0; m < swept.size(); ++m) markdown += "---|";
        markdown += "\n";
        for (const auto& point : sweep) {
            markdown += fmt::format("| {} |", point["gps"].get<int>());
            for (const std::string& m : swept) markdown += fmt::format(" {:.4g} |", point[m].get<double>());
            markdown += "\n";
        }
        output.add_text("frame_time_vs_gps.json", nlohmann::json{{"scenario", scaling->scenario},
                                                                 {"frame", scaling->frame},
                                                                 {"machine", scaling->machine},
                                                                 {"points", sweep}}
                                                          .dump(2) +
                                                      "\n");
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
    fmt::print("pp5sim reproduce: {} ({})\n", model->targets().name, uncalibrated ? "uncalibrated" : "calibrated");
    if (host) {
        fmt::print("  host check: median absolute error {:.1f}% fitted, {:.1f}% held out\n",
                   100 * host->median_fitted_error, 100 * host->median_held_out_error);
    }
    print_summary(report);
    fmt::print("  {} images; plots {}{}\n", images, plot_names, scaling ? "frame_time_vs_gps.png" : "");
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
