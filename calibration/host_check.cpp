#include "calibration/host_check.h"

#include "kernels/registry/run_config.h"
#include "scene/reference/reference_costs.h"
#include "scene/reference/reference_renderer.h"
#include "scene/scenario/scenario.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/components/gp_cost_model.h"
#include "sim/core/time.h"
#include "sim/timing/frame_engine.h"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace pp5 {

namespace {

// log(predicted / measured) of one case, linear in the two scales.
struct HostResidual {
    double flop_seconds;
    double cycle_seconds;
    double measured;
    template <class T>
    bool operator()(const T* const scales, T* residual) const {
        residual[0] = log((scales[0] * flop_seconds + scales[1] * cycle_seconds) / measured);
        return true;
    }
};

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

HostCheckReport run_host_check(const MachineConfig& host, const HostCheckOptions& options) {
    HostCheckReport report;
    // One thread: the model prices one processor's work.
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    const GpCostModel costs = GpCostModel::from(host);
    const std::vector<Tick> loop_costs =
        gp_op_costs(host, {{"ray_setup", reference_ray_setup_cost_keys()}, {"sample", reference_sample_cost_keys()}});
    int index = 0;
    for (const std::string& name : options.scenarios) {
        const Scenario scenario = load_scenario(resolve_scenario_file(name));
        const Volume volume = load_dataset(scenario);
        ReferenceRenderer renderer(volume);
        const FrameSpec& frame = scenario.frames.front();
        renderer.set_classification(frame.classification, frame.colors);
        renderer.set_lighting(frame.lighting);
        const Camera camera = frame_camera(frame, volume);
        for (const int size : options.image_sizes) {
            HostCase c;
            c.scenario = name;
            c.image_size = size;
            c.fitted = index++ % 2 == 0;
            RenderSettings settings = reference_render_settings(scenario.image);
            settings.width = settings.height = size;
            RenderStats stats;
            (void)renderer.render(camera, settings, &stats);  // classifies, shades on demand: not timed
            c.measured_seconds = std::numeric_limits<double>::infinity();
            for (int r = 0; r < std::max(1, options.repeats); ++r) {
                (void)renderer.render(camera, settings, &stats);
                c.measured_seconds = std::min(c.measured_seconds, stats.seconds.compositing);
            }
            c.rays = stats.composite.rays;
            c.samples = stats.composite.samples;
            c.samples_skipped = stats.composite.samples_skipped;
            c.flop_seconds = ticks_to_seconds(static_cast<Tick>(c.rays) * loop_costs[0] +
                                              static_cast<Tick>(c.samples) * loop_costs[1]);
            c.voxels = static_cast<std::uint64_t>(volume.voxel_count());
            c.cycle_seconds = ticks_to_seconds(static_cast<Tick>(c.voxels) * costs.receive_per_word);
            if (options.progress)
                options.progress(fmt::format("host check: {} at {}x{}: {:.1f} ms, {} samples", name, size, size,
                                             1e3 * c.measured_seconds, c.samples));
            report.cases.push_back(c);
        }
    }

    fit_host_cases(report);
    return report;
}

void fit_host_cases(HostCheckReport& report) {
    double scales[2] = {1.0, 1.0};
    ceres::Problem problem;
    for (const HostCase& c : report.cases) {
        if (!c.fitted) continue;
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<HostResidual, 1, 2>(
                                     new HostResidual{c.flop_seconds, c.cycle_seconds, c.measured_seconds}),
                                 nullptr, scales);
    }
    problem.SetParameterLowerBound(scales, 0, 1e-3);
    problem.SetParameterLowerBound(scales, 1, 0.0);
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    report.solver = fmt::format("{} iterations, final cost {:.4g}; {}", summary.iterations.size(), summary.final_cost,
                                summary.message);
    report.gp_flops_scale = scales[0];
    report.gp_cycles_scale = scales[1];

    // Standard errors, scaled by the residuals' spread (the cases carry no stated uncertainty).
    int fitted = 0;
    for (const HostCase& c : report.cases) fitted += c.fitted;
    ceres::Covariance::Options cov_options;
    cov_options.algorithm_type = ceres::DENSE_SVD;
    cov_options.null_space_rank = -1;
    ceres::Covariance covariance(cov_options);
    double cov[4] = {NAN, NAN, NAN, NAN};
    const std::vector<std::pair<const double*, const double*>> blocks{{scales, scales}};
    if (fitted > 2 && covariance.Compute(blocks, &problem) && covariance.GetCovarianceBlock(scales, scales, cov)) {
        const double spread = 2.0 * summary.final_cost / (fitted - 2);
        report.gp_flops_standard_error = std::sqrt(cov[0] * spread);
        report.gp_cycles_standard_error = std::sqrt(cov[3] * spread);
    } else {
        report.gp_flops_standard_error = report.gp_cycles_standard_error = std::numeric_limits<double>::quiet_NaN();
    }

    std::vector<double> fitted_errors, held_errors;
    for (HostCase& c : report.cases) {
        c.predicted_seconds = scales[0] * c.flop_seconds + scales[1] * c.cycle_seconds;
        (c.fitted ? fitted_errors : held_errors).push_back(std::abs(c.relative_error()));
    }
    report.median_fitted_error = median(fitted_errors);
    report.median_held_out_error = median(held_errors);
    report.max_held_out_error = held_errors.empty() ? 0.0 : *std::max_element(held_errors.begin(), held_errors.end());
}

nlohmann::json HostCheckReport::to_json() const {
    nlohmann::json rows = nlohmann::json::array();
    for (const HostCase& c : cases) {
        rows.push_back({{"scenario", c.scenario},
                        {"image_size", c.image_size},
                        {"use", c.fitted ? "fitted" : "held-out"},
                        {"rays", c.rays},
                        {"samples", c.samples},
                        {"samples_skipped", c.samples_skipped},
                        {"voxels", c.voxels},
                        {"measured_seconds", c.measured_seconds},
                        {"predicted_seconds", c.predicted_seconds},
                        {"relative_error", c.relative_error()}});
    }
    const auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return {{"parameters",
             {{"calibration.gp_flops_scale",
               {{"value", gp_flops_scale}, {"standard_error", finite(gp_flops_standard_error)}}},
              {"calibration.gp_cycles_scale",
               {{"value", gp_cycles_scale}, {"standard_error", finite(gp_cycles_standard_error)}}}}},
            {"cases", rows},
            {"median_abs_error_fitted", median_fitted_error},
            {"median_abs_error_held_out", median_held_out_error},
            {"max_abs_error_held_out", max_held_out_error},
            {"solver", solver}};
}

std::string HostCheckReport::to_markdown() const {
    std::ostringstream md;
    md << "# The model against this machine (host preset)\n\n"
       << "pp5sim's reference renderer, one thread, best of several runs, priced by the GP cost model's operation "
          "counts: "
          "ray setup per ray and step, interpolation and compositing per sample (flops), and each voxel of the volume "
          "brought through the memory hierarchy once a frame, priced as a GP copies a received word into its cache "
          "(cycles).\n\n"
       << fmt::format(
              "Fitted on half the cases: `calibration.gp_flops_scale` = {:.4g} +/- {:.2g}, "
              "`calibration.gp_cycles_scale` = {:.4g} +/- {:.2g} ({}).\n\n",
              gp_flops_scale, gp_flops_standard_error, gp_cycles_scale, gp_cycles_standard_error, solver)
       << fmt::format(
              "**Median absolute error: {:.1f}% on the fitted half, {:.1f}% on the held-out half (max {:.1f}%).**\n\n",
              100 * median_fitted_error, 100 * median_held_out_error, 100 * max_held_out_error)
       << "| scenario | image | use | voxels | samples | measured (ms) | predicted (ms) | error "
          "|\n|---|---|---|---|---|---|---|---|\n";
    for (const HostCase& c : cases) {
        md << fmt::format("| {} | {}x{} | {} | {} | {} | {:.2f} | {:.2f} | {:+.1f}% |\n", c.scenario, c.image_size,
                          c.image_size, c.fitted ? "fitted" : "held out", c.voxels, c.samples, 1e3 * c.measured_seconds,
                          1e3 * c.predicted_seconds, 100 * c.relative_error());
    }
    return md.str();
}

}  // namespace pp5
