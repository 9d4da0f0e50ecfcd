#include "calibration/workload.h"

#include "sim/core/calibration.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

namespace pp5 {

namespace {

// One parameter's search: each trial records the two rows' scenarios with the trial value set.
class RatioSearch {
public:
    RatioSearch(const TargetSet& targets, const WorkloadSpec& spec, const MachineConfig& functional,
                std::vector<WorkloadSetting> earlier, const WorkloadOptions& options)
        : spec_(spec), functional_(functional), earlier_(std::move(earlier)), options_(options) {
        rows_.file = targets.file;
        rows_.name = targets.name;
        rows_.targets = {*targets.find(spec.numerator), *targets.find(spec.denominator)};
        reported_ = rows_.targets[0].reported / rows_.targets[1].reported;
    }

    double reported_ratio() const { return reported_; }
    int trials() const { return trials_; }

    // The simulated ratio at `value`.
    double ratio(double value) {
        std::vector<WorkloadSetting> settings = earlier_;
        settings.push_back({spec_.key, value, spec_.integer});
        const CalibrationModel model(rows_, functional_, settings);
        const std::string& machine = rows_.targets[0].machine;
        const CalibrationScales scales = CalibrationScales::from(model.base_config(machine));
        const std::vector<double> v =
            model.simulate(machine, scales, {&model.targets().targets[0], &model.targets().targets[1]});
        ++trials_;
        const double r = v[0] / v[1];
        if (!(r > 0.0) || !std::isfinite(r))
            throw InputError(rows_.file.string(), "workload " + spec_.key,
                             fmt::format("at {} the rows' simulated ratio is {}: it cannot be searched", value, r));
        if (options_.progress)
            options_.progress(fmt::format("workload: {} = {:.6g} gives {} / {} = {:.4g} (reported {:.4g})", spec_.key,
                                          value, spec_.numerator, spec_.denominator, r, reported_));
        return r;
    }
    // How far the ratio at `value` is from the reported one, in log units.
    double miss(double value) { return std::log(ratio(value) / reported_); }

private:
    const WorkloadSpec& spec_;
    const MachineConfig& functional_;
    std::vector<WorkloadSetting> earlier_;
    const WorkloadOptions& options_;
    TargetSet rows_;
    double reported_ = 1.0;
    int trials_ = 0;
};

constexpr int kMostTrials = 16;
constexpr double kRatioTolerance = 0.005;  // half a percent: well inside any measurement's 10%

IdentifiedWorkload identify_one(const TargetSet& targets, const WorkloadSpec& spec, const MachineConfig& functional,
                                const std::vector<WorkloadSetting>& earlier, const WorkloadOptions& options) {
    RatioSearch search(targets, spec, functional, earlier, options);
    IdentifiedWorkload id;
    id.spec = spec;
    id.reported_ratio = search.reported_ratio();
    id.machine_value = spec.integer ? ParamValue(functional.integer(spec.key)) : ParamValue(functional.real(spec.key));

    double a = spec.lower, b = spec.upper;
    double fa = search.miss(a), fb = 0.0;
    const double f_lower = fa;
    if (spec.integer && fa != 0.0) {
        // A whole-number parameter here is a count of work (samples a voxel, say): the upper bound is
        // the dearest trial of all. Bracket from the lower bound outwards, doubling the step.
        for (double step = 1.0;; step *= 2.0) {
            const double x = std::min(a + step, spec.upper);
            const double fx = search.miss(x);
            if (fx == 0.0 || (fx > 0.0) != (fa > 0.0) || x >= spec.upper) {
                b = x, fb = fx;
                break;
            }
            a = x, fa = fx;
        }
    } else {
        fb = search.miss(b);
    }
    const auto finish = [&](double value, double miss) {
        id.value = value;
        id.simulated_ratio = id.reported_ratio * std::exp(miss);
        id.trials = search.trials();
        return id;
    };
    if (fa == 0.0) return finish(a, fa);
    if (fb == 0.0) return finish(b, fb);
    if ((fa > 0.0) == (fb > 0.0)) {
        // The ratio does not cross the reported one inside the bounds: keep the nearer end, and say so.
        id.at_bound = true;
        id.note = fmt::format(
            "the reported ratio {:.4g} lies outside what [{}, {}] gives ({:.4g} to {:.4g}): held at the nearer bound",
            id.reported_ratio, spec.lower, spec.upper, id.reported_ratio * std::exp(f_lower),
            id.reported_ratio * std::exp(fb));
        return std::abs(f_lower) <= std::abs(fb) ? finish(spec.lower, f_lower) : finish(spec.upper, fb);
    }
    // False position with the Illinois correction: an end that stays twice has its miss halved, so
    // the bracket shrinks from both sides even when the ratio curves.
    int kept_side = 0;
    double best = std::abs(fa) < std::abs(fb) ? a : b, best_miss = std::abs(fa) < std::abs(fb) ? fa : fb;
    while (search.trials() < kMostTrials) {
        if (spec.integer && b - a <= 1.0) break;
        double x = (a * fb - b * fa) / (fb - fa);
        if (spec.integer) x = std::clamp(std::round(x), a + 1.0, b - 1.0);
        const double fx = search.miss(x);
        if (std::abs(fx) < std::abs(best_miss)) best = x, best_miss = fx;
        if (std::abs(fx) < kRatioTolerance) break;
        if ((fx > 0.0) == (fa > 0.0)) {
            a = x, fa = fx;
            if (kept_side == 1) fb /= 2.0;
            kept_side = 1;
        } else {
            b = x, fb = fx;
            if (kept_side == -1) fa /= 2.0;
            kept_side = -1;
        }
        if (!spec.integer && b - a < 1e-6 * (spec.upper - spec.lower)) break;
    }
    if (spec.integer && std::abs(best_miss) >= kRatioTolerance)
        id.note = fmt::format("the nearest whole value; the reported ratio lies between {} and {}", a, b);
    return finish(best, best_miss);
}

}  // namespace

std::vector<IdentifiedWorkload> identify_workload(const TargetSet& targets, const WorkloadOptions& options) {
    std::vector<IdentifiedWorkload> identified;
    if (targets.workload.empty()) return identified;
    const MachineConfig functional = recording_machine(targets);
    for (const WorkloadSpec& spec : targets.workload)
        identified.push_back(identify_one(targets, spec, functional, workload_settings(identified), options));
    return identified;
}

std::vector<WorkloadSetting> workload_settings(const std::vector<IdentifiedWorkload>& identified) {
    std::vector<WorkloadSetting> settings;
    for (const IdentifiedWorkload& w : identified) settings.push_back({w.spec.key, w.value, w.spec.integer});
    return settings;
}

}  // namespace pp5
