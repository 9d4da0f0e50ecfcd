#pragma once
// Internal to calibration/: one machine's fit (fit.cpp drives it, once for all its fitted rows and
// once per row left out). The free scales are solved for in their logarithms by Ceres, robustly, each
// residual the log ratio of a simulated figure to the paper's in units of its source's uncertainty.

#include "calibration/fit_detail.h"
#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "sim/core/calibration.h"

#include <ceres/ceres.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pp5::fit_detail {

// A target's residual: ln(simulated / reported) in units of its source's relative uncertainty.
double residual(const Target& t, double simulated);

class MachineFit {
public:
    MachineFit(const CalibrationModel& model, std::string machine, std::vector<const Target*> targets,
               CalibrationScales start, std::vector<int> free, std::vector<ScaleBounds> bounds);

    // The solver works in the scales' logarithms: the residuals are log ratios, and a scale multiplies
    // a cost, so in log space the problem is close to linear and the Levenberg-Marquardt steps land.
    CalibrationScales scales(const double* log_x) const;
    std::vector<double> log_start() const;
    // Each target's residual at `s` (one simulation of every target).
    std::vector<double> residuals(const CalibrationScales& s) const;
    // The least-squares problem over `x`: robust for fitting, plain for the covariance at the solution
    // (a robust loss's down-weighting would otherwise inflate the standard errors of a poor fit twice).
    std::unique_ptr<ceres::Problem> problem(std::vector<double>& x, bool robust) const;
    // Solves from `x` (updated in place).
    ceres::Solver::Summary solve(std::vector<double>& x, int max_iterations) const;
    // Ceres' covariance of the log scales at the solution `x`, from the plain problem; none when the
    // Jacobian is rank-deficient.
    std::optional<std::vector<double>> log_covariance(std::vector<double>& x) const;

    const std::vector<const Target*>& targets() const { return targets_; }
    const std::vector<int>& free() const { return free_; }
    const std::string& machine() const { return machine_; }
    // The same fit (machine, start, free scales, bounds) over other rows, on `model`.
    MachineFit on(const CalibrationModel& model, std::vector<const Target*> targets) const;
    int simulations() const { return simulations_.load(); }

private:
    class Residuals;

    const CalibrationModel& model_;
    std::string machine_;
    std::vector<const Target*> targets_;
    CalibrationScales start_;
    std::vector<int> free_;
    std::vector<ScaleBounds> bounds_;          // every scale's, in kScales' order
    mutable std::atomic<int> simulations_{0};  // the targets simulated so far (a Jacobian's run side by side)
};

}  // namespace pp5::fit_detail
