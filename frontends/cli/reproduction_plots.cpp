#include "frontends/cli/reproduction_plots.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <optional>

namespace pp5::cli {

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

GpSweepFrame gp_sweep_frame(const CalibrationModel& model) {
    GpSweepFrame sweep;
    for (const Target& t : model.targets().targets)
        if (!sweep.target && !t.is_formula() &&
            model.base_config(t.machine).machine_kind() == MachineKind::Multicomputer && t.unit == "s")
            sweep.target = &t;
    if (!sweep.target) return sweep;
    const Target& s = *sweep.target;
    for (const Target& t : model.targets().targets)
        if (t.scenario == s.scenario && t.frame == s.frame && t.machine == s.machine && t.unit == "s" &&
            std::find(sweep.metrics.begin(), sweep.metrics.end(), t.metric) == sweep.metrics.end())
            sweep.metrics.push_back(t.metric);
    return sweep;
}

namespace {

// The swept frame re-timed at each GP count with the report's scales: a point per count, each metric's
// seconds, and the plot's series.
nlohmann::json time_gp_counts(const CalibrationModel& model, const FitReport& report, const GpSweepFrame& sweep,
                              const std::vector<int>& gp_counts, std::vector<PlotSeries>& series,
                              const std::function<void(const std::string&)>& say) {
    const Target& s = *sweep.target;
    for (std::size_t m = 0; m < sweep.metrics.size(); ++m) {
        std::string title = sweep.metrics[m];  // gnuplot would read an underscore as a subscript
        std::replace(title.begin(), title.end(), '_', ' ');
        series.push_back(
            PlotSeries{title, {}, {}, fmt::format("linespoints pt {} lw 2", 7 - 2 * static_cast<int>(m % 3)), {}, {}});
    }
    nlohmann::json points = nlohmann::json::array();
    const CalibrationScales scales = report.scales(s.machine);
    for (const int n : gp_counts) {
        say(fmt::format("GP sweep: {} GPs", n));
        MachineConfig config = model.machine_config(s.machine, scales);
        config.set("gp.count", static_cast<std::int64_t>(n), "--gp-counts");
        const RecordedScenario& recording = model.recording(s.scenario);
        const auto frame = static_cast<std::size_t>(s.frame);
        const FrameTiming timing = recording.time_on(config, frame + 1)[frame];
        nlohmann::json point = {{"gps", n}};
        for (std::size_t m = 0; m < sweep.metrics.size(); ++m) {
            const double seconds = recording.metric(sweep.metrics[m], frame, timing);
            series[m].x.push_back(n);
            series[m].y.push_back(seconds);
            point[sweep.metrics[m]] = seconds;
        }
        points.push_back(point);
    }
    return points;
}

}  // namespace

GpSweep gp_sweep(const CalibrationModel& model, const FitReport& report, const GpSweepFrame& sweep,
                 const std::vector<int>& gp_counts, bool uncalibrated,
                 const std::function<void(const std::string&)>& say) {
    GpSweep out;
    std::string& markdown = out.markdown;
    const Target& s = *sweep.target;
    PlotSpec spec;
    spec.title = fmt::format("Frame time against GP count ({}, frame {}, {})", s.scenario, s.frame,
                             uncalibrated ? "uncalibrated" : "calibrated");
    spec.x_label = "graphics processors";
    spec.y_label = "simulated frame time (s)";
    spec.log_x = spec.log_y = true;
    const int most = *std::max_element(gp_counts.begin(), gp_counts.end());
    const int fewest = *std::min_element(gp_counts.begin(), gp_counts.end());
    spec.extra_commands = {"set xtics (1,2,4,8,16,32,64,128,256,512,1024)",
                           fmt::format("set xrange [{}:{}]", 0.8 * fewest, 1.25 * most)};
    std::vector<PlotSeries> series;
    const nlohmann::json points = time_gp_counts(model, report, sweep, gp_counts, series, say);
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
    for (const Target& t : model.targets().targets) {
        if (t.scenario != s.scenario || t.frame != s.frame || t.machine != s.machine) continue;
        if (std::find(sweep.metrics.begin(), sweep.metrics.end(), t.metric) == sweep.metrics.end()) continue;
        const double gps = static_cast<double>(model.base_config(t.machine).integer("gp.count"));
        spec.series.push_back(PlotSeries{"reported: " + t.id, {gps}, {t.reported}, "points pt 9 ps 2.5", {}, {}});
    }
    markdown += fmt::format(
        "\n## Frame time against GP count\n\n![frame time against GP count](frame_time_vs_gps.png)\n\n`{}` frame "
        "{} on {} "
        "with the {} scales, the GP count varied (data: frame_time_vs_gps.json).\n\n| GPs |",
        s.scenario, s.frame, s.machine, uncalibrated ? "uncalibrated" : "fitted");
    for (const std::string& m : sweep.metrics) markdown += " " + m + " (s) |";
    markdown += "\n|---|";
    for (std::size_t m = 0; m < sweep.metrics.size(); ++m) markdown += "---|";
    markdown += "\n";
    for (const auto& point : points) {
        markdown += fmt::format("| {} |", point["gps"].get<int>());
        for (const std::string& m : sweep.metrics) markdown += fmt::format(" {:.4g} |", point[m].get<double>());
        markdown += "\n";
    }
    out.data = nlohmann::json{{"scenario", s.scenario}, {"frame", s.frame}, {"machine", s.machine}, {"points", points}};
    out.plot = std::move(spec);
    return out;
}

}  // namespace pp5::cli
