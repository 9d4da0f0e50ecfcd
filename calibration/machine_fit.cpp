#include "calibration/machine_fit.h"

#include "sim/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

namespace pp5::fit_detail {

namespace {

// Residuals are in units of their source's uncertainty; beyond about two of those the Cauchy loss
// discounts a target (an estimate 65% off, a measurement 22% off).
constexpr double kLossScale = 2.0;

}  // namespace

double residual(const Target& t, double simulated) {
    return std::log(simulated / t.reported) / relative_uncertainty(t.exactness);
}

// The targets' residuals and their central-difference Jacobian. Each evaluation is a whole
// simulation, and the 2n + 1 of a Jacobian are independent: they run side by side, so a fit uses
// every core and still gives the same numbers at any thread count.
class MachineFit::Residuals final : public ceres::CostFunction {
public:
    Residuals(const MachineFit& fit, int scales) : fit_(fit) {
        set_num_residuals(static_cast<int>(fit.targets_.size()));
        mutable_parameter_block_sizes()->push_back(scales);
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        const std::size_t n = static_cast<std::size_t>(parameter_block_sizes().front());
        const std::vector<double> x(parameters[0], parameters[0] + n);
        const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
        // Point 0 is x; points 2i+1 and 2i+2 step scale i up and down.
        std::vector<std::vector<double>> points(want_jacobian ? 2 * n + 1 : 1, x);
        std::vector<double> steps(n);
        for (std::size_t i = 0; want_jacobian && i < n; ++i) {
            // Costs are whole picoseconds and events discrete, so the cost jumps a little from one
            // scale to the next: a step of 5% spans those jumps and gives the slope they sit on.
            steps[i] = kLogStep;
            points[2 * i + 1][i] += steps[i];
            points[2 * i + 2][i] -= steps[i];
        }
        // Ceres often asks about the same point twice or three times running (its cost, then its
        // Jacobian; a Jacobian, then the cost again): the simulations it needs were run already.
        std::vector<std::vector<double>> values(points.size());
        {
            const std::lock_guard<std::mutex> lock(last_mutex_);
            if (last_x_ == x)
                for (std::size_t p = 0; p < values.size() && p < last_values_.size(); ++p) values[p] = last_values_[p];
        }
        pp5::parallel_for(std::size_t{0}, points.size(), [&](std::size_t p) {
            if (values[p].empty()) values[p] = fit_.residuals(fit_.scales(points[p].data()));
        });
        {
            const std::lock_guard<std::mutex> lock(last_mutex_);
            if (last_x_ != x || values.size() >= last_values_.size()) last_values_ = values;
            last_x_ = x;
        }
        const std::size_t m = values.front().size();
        for (std::size_t r = 0; r < m; ++r) {
            residuals[r] = values.front()[r];
            for (std::size_t i = 0; want_jacobian && i < n; ++i)
                jacobians[0][r * n + i] = (values[2 * i + 1][r] - values[2 * i + 2][r]) / (2.0 * steps[i]);
        }
        for (const std::vector<double>& v : values)
            if (!std::all_of(v.begin(), v.end(), [](double e) { return std::isfinite(e); })) return false;
        return true;
    }

private:
    static constexpr double kLogStep = 0.05;
    const MachineFit& fit_;
    mutable std::mutex last_mutex_;
    mutable std::vector<double> last_x_;  // the last point evaluated, and the residuals of its points
    mutable std::vector<std::vector<double>> last_values_;
};

MachineFit::MachineFit(const CalibrationModel& model, std::string machine, std::vector<const Target*> targets,
                       CalibrationScales start, std::vector<int> free, std::vector<ScaleBounds> bounds)
    : model_(model),
      machine_(std::move(machine)),
      targets_(std::move(targets)),
      start_(start),
      free_(std::move(free)),
      bounds_(std::move(bounds)) {}

CalibrationScales MachineFit::scales(const double* log_x) const {
    CalibrationScales s = start_;
    for (std::size_t i = 0; i < free_.size(); ++i) s.*kScales[free_[i]].member = std::exp(log_x[i]);
    return s;
}

std::vector<double> MachineFit::log_start() const {
    std::vector<double> x;
    for (int j : free_) x.push_back(std::log(start_.*kScales[j].member));
    return x;
}

std::vector<double> MachineFit::residuals(const CalibrationScales& s) const {
    ++simulations_;
    const std::vector<double> simulated = model_.simulate(machine_, s, targets_);
    std::vector<double> r;
    for (std::size_t i = 0; i < targets_.size(); ++i) r.push_back(residual(*targets_[i], simulated[i]));
    return r;
}

std::unique_ptr<ceres::Problem> MachineFit::problem(std::vector<double>& x, bool robust) const {
    auto problem = std::make_unique<ceres::Problem>();
    problem->AddResidualBlock(new Residuals(*this, static_cast<int>(x.size())),
                              robust ? new ceres::CauchyLoss(kLossScale) : nullptr, x.data());
    for (std::size_t i = 0; i < x.size(); ++i) {
        problem->SetParameterLowerBound(x.data(), static_cast<int>(i),
                                        std::log(bounds_[static_cast<std::size_t>(free_[i])].lower));
        problem->SetParameterUpperBound(x.data(), static_cast<int>(i),
                                        std::log(bounds_[static_cast<std::size_t>(free_[i])].upper));
    }
    return problem;
}

ceres::Solver::Summary MachineFit::solve(std::vector<double>& x, int max_iterations) const {
    const std::unique_ptr<ceres::Problem> robust = problem(x, true);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = max_iterations;
    // Stop once the scales settle to four significant digits: every simulation is a whole frame,
    // and the fitted scales' standard errors are tens of percent, so more digits only cost time.
    options.function_tolerance = 1e-5;
    options.parameter_tolerance = 1e-3;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    options.num_threads = 1;  // one residual block, whose Jacobian runs its simulations side by side
    // With bounds, Ceres follows every trust-region step with a projected Armijo line search. Its
    // default cubic interpolation wants the gradient at each trial point, which here is a whole
    // Jacobian (2n + 1 simulations); a quadratic through the start's value and slope and the trial's
    // value needs one simulation a trial. Past a few trials on this noisy, event-driven cost the
    // search only shrinks the step towards nothing: the trust region does that job for less.
    options.line_search_interpolation_type = ceres::QUADRATIC;
    options.max_num_line_search_step_size_iterations = 4;
    ceres::Solver::Summary summary;
    ceres::Solve(options, robust.get(), &summary);
    return summary;
}

MachineFit MachineFit::on(const CalibrationModel& model, std::vector<const Target*> targets) const {
    return MachineFit(model, machine_, std::move(targets), start_, free_, bounds_);
}

std::optional<std::vector<double>> MachineFit::log_covariance(std::vector<double>& x) const {
    const std::unique_ptr<ceres::Problem> plain = problem(x, false);
    ceres::Covariance::Options cov_options;
    cov_options.algorithm_type = ceres::DENSE_SVD;
    cov_options.null_space_rank = -1;
    ceres::Covariance covariance(cov_options);
    std::vector<double> cov(x.size() * x.size(), std::numeric_limits<double>::quiet_NaN());
    const std::vector<std::pair<const double*, const double*>> blocks{{x.data(), x.data()}};
    if (!covariance.Compute(blocks, plain.get()) || !covariance.GetCovarianceBlock(x.data(), x.data(), cov.data()))
        return std::nullopt;
    return cov;
}

}  // namespace pp5::fit_detail
