#include "calibration/residuals.h"

#include "calibration/fit_detail.h"
#include "sim/core/time.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace pp5 {

namespace {

constexpr std::size_t kOperationKindsShown = 4;

// Operations by kind, most frequent first.
std::vector<std::pair<std::string, double>> operations(const FrameWork& work, const std::vector<GpOp>& ops) {
    std::map<std::uint32_t, double> counts;
    for (const GpOp& op : ops) counts[op.kind] += op.count;
    std::vector<std::pair<std::string, double>> kinds;
    for (const auto& [kind, count] : counts)
        kinds.emplace_back(kind < work.op_kinds.size() ? work.op_kinds[kind].name : "?", count);
    std::sort(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    if (kinds.size() > kOperationKindsShown) kinds.resize(kOperationKindsShown);
    return kinds;
}

PhaseAccount account_of(const FrameWork& work, const PhaseTiming& timing) {
    PhaseAccount a{timing.name, ticks_to_seconds(timing.duration_ps()), {}};
    const auto phase =
        std::find_if(work.phases.begin(), work.phases.end(), [&](const Phase& p) { return p.name == timing.name; });
    if (phase == work.phases.end()) return a;
    if (const auto* pp = std::get_if<PpPhase>(&phase->work)) {
        a.work.emplace_back("PP programs", static_cast<double>(pp->passes.size()));
        double cycles_per_slot = 0.0;
        for (const PpPassTiming& pass : timing.passes)
            if (pass.slots > 0)
                cycles_per_slot += static_cast<double>(pass.busiest.total) / static_cast<double>(pass.slots);
        if (cycles_per_slot > 0.0) a.work.emplace_back("PP cycles per voxel slot", cycles_per_slot);
        if (timing.passes.empty()) {  // one processor: the same work as operations
            std::vector<GpOp> ops;
            for (const PpPhase::Pass& pass : pp->passes)
                ops.insert(ops.end(), pass.on_one_processor.begin(), pass.on_one_processor.end());
            for (auto& kind : operations(work, ops)) a.work.push_back(std::move(kind));
        }
    } else if (const auto* gp = std::get_if<GpPhase>(&phase->work)) {
        a.work.emplace_back("items (rays, batches)", static_cast<double>(gp->items.size()));
        for (auto& kind : operations(work, gp->ops)) a.work.push_back(std::move(kind));
        if (timing.gp.fetch_requests > 0)
            a.work.emplace_back("fetch requests", static_cast<double>(timing.gp.fetch_requests));
        if (timing.gp.cache_misses > 0)
            a.work.emplace_back("cache misses", static_cast<double>(timing.gp.cache_misses));
        // The crude pass's rows end with the first group (refinement pass), not the phase.
        if (timing.group_end_ps.size() > 1)
            a.work.emplace_back("seconds from its start to the end of its first pass",
                                ticks_to_seconds(timing.group_end_ps.front() - timing.start_ps));
        const double busy = static_cast<double>(timing.gp.gp_busy), wait = static_cast<double>(timing.gp.gp_wait);
        if (busy + wait > 0.0) a.work.emplace_back("GP busy fraction", busy / (busy + wait));
    } else if (const auto* broadcast = std::get_if<BroadcastPhase>(&phase->work)) {
        for (auto& kind : operations(work, broadcast->then_each_gp)) a.work.push_back(std::move(kind));
    }
    return a;
}

std::vector<PhaseAccount> accounts_of(const FrameWork& work, const FrameTiming& timing) {
    std::vector<PhaseAccount> accounts;
    for (const PhaseTiming& phase : timing.phases) accounts.push_back(account_of(work, phase));
    return accounts;
}

std::vector<std::pair<std::string, std::pair<double, double>>> phase_pairs(const FrameTiming& here,
                                                                           const FrameTiming& there) {
    std::vector<std::pair<std::string, std::pair<double, double>>> pairs;
    for (const PhaseTiming& p : here.phases) pairs.push_back({p.name, {ticks_to_seconds(p.duration_ps()), 0.0}});
    for (const PhaseTiming& p : there.phases) {
        auto it = std::find_if(pairs.begin(), pairs.end(), [&](const auto& e) { return e.first == p.name; });
        if (it == pairs.end()) it = pairs.insert(pairs.end(), {p.name, {0.0, 0.0}});
        it->second.second = ticks_to_seconds(p.duration_ps());
    }
    return pairs;
}

std::string amount(double v) {
    if (v >= 1e6) return fmt::format("{:.3g}M", v / 1e6);
    if (v >= 1e4) return fmt::format("{:.3g}k", v / 1e3);
    if (v >= 100 || v == std::floor(v)) return fmt::format("{:.0f}", v);
    return fmt::format("{:.3g}", v);
}

constexpr double kReconciledWithin = 0.02;

using fit_detail::percent;

}  // namespace

std::vector<ResidualAccount> explain_residuals(const CalibrationModel& model, const FitReport& report,
                                               double threshold) {
    std::vector<ResidualAccount> accounts;
    std::map<std::string, std::vector<const TargetResult*>> by_machine;
    for (const TargetResult& r : report.results)
        if (!r.target.is_formula()) by_machine[r.target.machine].push_back(&r);
    for (const auto& [machine, results] : by_machine) {
        if (std::none_of(results.begin(), results.end(),
                         [&](const TargetResult* r) { return std::abs(r->relative_error) > threshold; }))
            continue;
        std::vector<const Target*> rows;
        for (const TargetResult* r : results) rows.push_back(&r->target);
        const CalibrationScales scales = report.scales(machine);
        const MachineSensitivity sensitivity = measure_sensitivity(model, machine, scales, rows);
        const MachineConfig config = model.machine_config(machine, scales);
        // Each scenario timed once on the machine, up to the last frame any of its rows reads.
        std::map<std::string, std::size_t> frames_read;
        for (const TargetResult* r : results) {
            std::size_t& frames = frames_read[r->target.scenario];
            frames =
                std::max(frames, static_cast<std::size_t>(std::max(r->target.frame, r->target.divided_by_frame)) + 1);
        }
        std::map<std::string, std::vector<FrameTiming>> timed;
        for (const auto& [scenario, frames] : frames_read)
            timed[scenario] = model.recording(scenario).time_on(config, frames);
        for (std::size_t i = 0; i < results.size(); ++i) {
            const TargetResult& r = *results[i];
            if (std::abs(r.relative_error) <= threshold) continue;
            ResidualAccount a;
            a.id = r.target.id;
            a.relative_error = r.relative_error;
            a.needed_factor = r.target.reported / r.simulated;
            a.assumption = r.target.assumes;
            const RecordedScenario& recording = model.recording(r.target.scenario);
            const std::vector<FrameTiming>& timings = timed.at(r.target.scenario);
            const auto frame = static_cast<std::size_t>(r.target.frame);
            if (r.target.divided_by_frame < 0) {
                a.phases = accounts_of(recording.frames()[frame].frame->work, timings[frame]);
            } else {
                const auto by = static_cast<std::size_t>(r.target.divided_by_frame);
                a.against.push_back({fmt::format("frame {}", by), r.target.reported, r.simulated,
                                     phase_pairs(timings[frame], timings[by])});
            }
            // The other frames of the same scenario the paper timed by the same measure.
            for (const TargetResult* o : results) {
                if (o == &r || o->target.scenario != r.target.scenario || o->target.metric != r.target.metric ||
                    o->target.divided_by_frame >= 0 || r.target.divided_by_frame >= 0 ||
                    o->target.frame == r.target.frame)
                    continue;
                a.against.push_back({o->target.id, r.target.reported / o->target.reported, r.simulated / o->simulated,
                                     phase_pairs(timings[frame], timings[static_cast<std::size_t>(o->target.frame)])});
            }
            a.what_if = reconcile(model, sensitivity, i);
            a.reported = r.target.reported;
            for (const TargetResult* o : results) {
                a.other_rows.push_back(o->target.id);
                a.other_reported.push_back(o->target.reported);
            }
            a.before = sensitivity.simulated;
            accounts.push_back(std::move(a));
        }
    }
    return accounts;
}

std::string residuals_markdown(const std::vector<ResidualAccount>& accounts) {
    std::string md =
        "\n## Why rows miss\n\nEvery simulated row more than 10% off, explained from this run: where its simulated "
        "time goes, what "
        "the paper's figure would need, how it stands against the other frames the paper timed alike, the paper's own "
        "assumption where the target file quotes it, and the one documented timing parameter whose change would "
        "reconcile "
        "it (found by re-timing, moving the machine's other rows least), with what that change does to them.\n";
    if (accounts.empty()) return md + "\nNo row is more than 10% off.\n";
    for (const ResidualAccount& a : accounts) {
        md += fmt::format("\n### `{}`: {} off; the figure needs {:.3g}x the simulated value\n\n", a.id,
                          percent(a.relative_error), a.needed_factor);
        if (!a.assumption.empty()) md += fmt::format("- The paper assumes: {}\n", a.assumption);
        if (!a.phases.empty()) {
            double total = 0.0;
            for (const PhaseAccount& p : a.phases) total += p.seconds;
            md += "- Where the frame's simulated time goes:";
            for (const PhaseAccount& p : a.phases) {
                md += fmt::format(" {} {:.4g} s ({:.0f}%", p.name, p.seconds,
                                  total > 0 ? 100.0 * p.seconds / total : 0.0);
                for (const auto& [what, value] : p.work)
                    md += fmt::format("; {} {}", what,
                                      what == "GP busy fraction" ? fmt::format("{:.0f}%", 100 * value) : amount(value));
                md += ");";
            }
            md.back() = '\n';
        }
        for (const FrameComparison& c : a.against) {
            md += fmt::format(
                "- Against `{}`: reported ratio {:.3g}, simulated {:.3g}; by phase (this frame / that one):", c.other,
                c.reported_ratio, c.simulated_ratio);
            for (const auto& [phase, s] : c.phase_seconds)
                md += fmt::format(" {} {:.4g} / {:.4g} s;", phase, s.first, s.second);
            md.back() = '\n';
        }
        if (a.what_if) {
            const WhatIf& w = *a.what_if;
            const double left = (w.reached - a.reported) / a.reported;
            md += fmt::format(
                "- What-if: `{}` from {:.4g} to {:.4g}{} gives {:.4g} ({}{}). The other rows then:", w.key, w.from,
                w.to, w.within_range ? "" : " (the edge of its declared range)", w.reached, percent(left),
                std::abs(left) <= kReconciledWithin
                    ? ", reconciled"
                    : ": the nearest one change gets, so no single documented parameter accounts for it");
            for (std::size_t k = 0; k < a.other_rows.size() && k < w.others.size(); ++k)
                if (a.other_rows[k] != a.id)
                    md += fmt::format(" `{}` {}{};", a.other_rows[k],
                                      percent((w.others[k] - a.other_reported[k]) / a.other_reported[k]),
                                      std::abs(w.others[k] / a.before[k] - 1.0) < 0.005 ? " (unchanged)" : "");
            md.back() = '\n';
        } else {
            md += "- What-if: no single timing parameter moves this row enough (by at most 20x) to reconcile it.\n";
        }
    }
    return md;
}

nlohmann::json residuals_json(const std::vector<ResidualAccount>& accounts) {
    nlohmann::json out = nlohmann::json::array();
    for (const ResidualAccount& a : accounts) {
        nlohmann::json row{{"id", a.id}, {"relative_error", a.relative_error}, {"needed_factor", a.needed_factor}};
        if (!a.assumption.empty()) row["paper_assumes"] = a.assumption;
        nlohmann::json phases = nlohmann::json::array();
        for (const PhaseAccount& p : a.phases) {
            nlohmann::json work = nlohmann::json::object();
            for (const auto& [what, value] : p.work) work[what] = value;
            phases.push_back({{"phase", p.name}, {"seconds", p.seconds}, {"work", work}});
        }
        row["phases"] = phases;
        nlohmann::json against = nlohmann::json::array();
        for (const FrameComparison& c : a.against) {
            nlohmann::json by_phase = nlohmann::json::object();
            for (const auto& [phase, s] : c.phase_seconds) by_phase[phase] = {s.first, s.second};
            against.push_back({{"other", c.other},
                               {"reported_ratio", c.reported_ratio},
                               {"simulated_ratio", c.simulated_ratio},
                               {"phase_seconds", by_phase}});
        }
        row["against"] = against;
        if (a.what_if) {
            const WhatIf& w = *a.what_if;
            nlohmann::json others = nlohmann::json::object();
            for (std::size_t k = 0; k < a.other_rows.size() && k < w.others.size(); ++k)
                others[a.other_rows[k]] = {
                    {"simulated", w.others[k]},
                    {"relative_error", (w.others[k] - a.other_reported[k]) / a.other_reported[k]}};
            row["what_if"] = {{"parameter", w.key},   {"from", w.from}, {"to", w.to}, {"within_range", w.within_range},
                              {"reached", w.reached}, {"rows", others}};
        } else {
            row["what_if"] = nullptr;
        }
        out.push_back(row);
    }
    return out;
}

}  // namespace pp5
