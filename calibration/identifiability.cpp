#include "calibration/identifiability.h"

#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pp5::fit_detail {

namespace {

constexpr double kStep = 1.1;                    // each scale moved by 10%
constexpr double kIdentifiableElasticity = 0.2;  // a 10% change of the scale moves some target by 2%
constexpr double kCollinearCosine = 0.98;

// Scales that move no fitted target enough are held.
void hold_unidentifiable(const ScaleResponse& response, std::vector<FittedParameter>& params, std::vector<int>& free) {
    for (int j = 0; j < kScaleCount; ++j) {
        const auto s = static_cast<std::size_t>(j);
        if (response.max_elasticity[s] >= kIdentifiableElasticity) {
            free.push_back(j);
            continue;
        }
        params[s].free = false;
        params[s].note =
            fmt::format("not identifiable: a 10% change moves no fitted target by more than {:.2f}%; held at {}",
                        100.0 * (std::pow(kStep, response.max_elasticity[s]) - 1.0), params[s].value);
    }
}

// Nearly parallel columns: the targets cannot separate the two scales, so the weaker of the most
// nearly parallel pair is held, until no pair is that close.
void hold_collinear(const ScaleResponse& response, std::vector<FittedParameter>& params, std::vector<int>& free) {
    for (;;) {
        double worst = kCollinearCosine;
        std::size_t weaker = 0, stronger = 0;
        bool found = false;
        for (std::size_t a = 0; a < free.size(); ++a)
            for (std::size_t b = a + 1; b < free.size(); ++b) {
                const double cosine = std::abs(response.cosine(free[a], free[b]));
                if (cosine < worst) continue;
                worst = cosine;
                const bool a_weaker = response.strength(free[a]) < response.strength(free[b]);
                weaker = a_weaker ? a : b;
                stronger = a_weaker ? b : a;
                found = true;
            }
        if (!found) return;
        FittedParameter& p = params[static_cast<std::size_t>(free[weaker])];
        p.free = false;
        p.note =
            fmt::format("not identifiable apart from {}: the targets respond to both alike (cosine {:.3f}); held at {}",
                        key_of(kScales[free[stronger]]), worst, p.value);
        free.erase(free.begin() + static_cast<std::ptrdiff_t>(weaker));
    }
}

// Fewer free scales than half the fitted targets, so that no scale is pinned by one figure alone:
// while there are more, the one that moves the targets least is held.
void hold_beyond_half(const ScaleResponse& response, std::vector<FittedParameter>& params, std::vector<int>& free,
                      std::size_t target_count, const std::string& machine, const std::string& targets_file) {
    const std::size_t allowed = (target_count - 1) / 2;
    if (!free.empty() && allowed == 0) {
        throw InputError(
            targets_file, "targets",
            fmt::format("machine {} has {} fitted target(s); a fit frees fewer scales than half its targets, so it "
                        "needs at least 3 (mark more rows use = \"fit\")",
                        machine, target_count));
    }
    while (free.size() > allowed) {
        const auto weakest = std::min_element(
            free.begin(), free.end(), [&](int a, int b) { return response.strength(a) < response.strength(b); });
        FittedParameter& p = params[static_cast<std::size_t>(*weakest)];
        p.free = false;
        p.note = fmt::format(
            "held at {}: {} fitted targets allow at most {} free scale(s) (fewer than half), and this one moves "
            "them least",
            p.value, target_count, allowed);
        free.erase(weakest);
    }
}

}  // namespace

double ScaleResponse::strength(int scale) const {
    double s = 0;
    for (double v : columns[static_cast<std::size_t>(scale)]) s += v * v;
    return std::sqrt(s);
}

double ScaleResponse::cosine(int scale, int other) const {
    const auto& ci = columns[static_cast<std::size_t>(scale)];
    const auto& cj = columns[static_cast<std::size_t>(other)];
    double dot = 0;
    for (std::size_t t = 0; t < ci.size(); ++t) dot += ci[t] * cj[t];
    return dot / (strength(scale) * strength(other));
}

ScaleResponse measure_scale_response(const CalibrationModel& model, const std::string& machine,
                                     const std::vector<const Target*>& targets, const CalibrationScales& start) {
    // The base and each moved scale are independent runs: simulated side by side.
    std::vector<std::vector<double>> runs(kScaleCount + 1);
    pp5::parallel_for(std::size_t{0}, runs.size(), [&](std::size_t run) {
        CalibrationScales scales = start;
        if (run > 0) scales.*kScales[run - 1].member *= kStep;
        runs[run] = model.simulate(machine, scales, targets);
    });
    const std::vector<double>& base = runs.front();
    ScaleResponse response;
    response.columns.resize(kScaleCount);
    response.max_elasticity.assign(kScaleCount, 0.0);
    for (std::size_t j = 0; j < static_cast<std::size_t>(kScaleCount); ++j) {
        const std::vector<double>& moved = runs[j + 1];
        for (std::size_t i = 0; i < targets.size(); ++i) {
            const double elasticity = std::log(moved[i] / base[i]) / std::log(kStep);
            response.columns[j].push_back(elasticity / relative_uncertainty(targets[i]->exactness));
            response.max_elasticity[j] = std::max(response.max_elasticity[j], std::abs(elasticity));
        }
    }
    return response;
}

std::vector<int> choose_free_scales(const ScaleResponse& response, std::vector<FittedParameter>& params,
                                    std::size_t target_count, const std::string& machine,
                                    const std::string& targets_file, std::vector<std::string>& notes) {
    std::vector<int> free;
    hold_unidentifiable(response, params, free);
    for (std::size_t a = 0; a < free.size(); ++a)
        for (std::size_t b = a + 1; b < free.size(); ++b)
            notes.push_back(fmt::format("{}: {} and {} move the fitted targets alike with cosine {:.3f} (at the start)",
                                        machine, key_of(kScales[free[a]]), key_of(kScales[free[b]]),
                                        response.cosine(free[a], free[b])));
    hold_collinear(response, params, free);
    hold_beyond_half(response, params, free, target_count, machine, targets_file);
    return free;
}

}  // namespace pp5::fit_detail
