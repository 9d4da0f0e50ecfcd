#include "frontends/sweep/sweep_run.h"

#include "calibration/timing_model.h"
#include "calibration/uncertainty.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"
#include "sim/core/parallel.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <compare>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

namespace pp5 {

namespace {

// What every frame has, whatever its kernel: from the timing engine's own counts.
const std::vector<SweepColumn>& machine_columns() {
    static const std::vector<SweepColumn> columns = {
        {"simulated_seconds", "s", "the frame's simulated time"},
        {"gp_utilisation", "fraction", "GP busy time over the GP count times the frame time (all phases)"},
        {"ring_utilisation", "fraction", "ring busy time over the channel count times the frame time (all phases)"},
        {"cache_hit_rate", "fraction", "GP cache look-ups that hit"},
        {"fetch_requests", "count", "fetch requests the GPs sent to renderers"},
        {"events", "count", "events the timing engine ran"},
    };
    return columns;
}

std::vector<double> machine_values(const FrameTiming& timing, const MachineConfig& config) {
    GpPhaseCounts sum;
    for (const PhaseTiming& p : timing.phases) {
        sum.cache_hits += p.gp.cache_hits;
        sum.cache_misses += p.gp.cache_misses;
        sum.fetch_requests += p.gp.fetch_requests;
        sum.events += p.gp.events;
    }
    const std::uint64_t lookups = sum.cache_hits + sum.cache_misses;
    return {ticks_to_seconds(timing.duration_ps()),
            timing.activity.gps,
            config.machine_kind() == MachineKind::Multicomputer ? timing.activity.ring : 0.0,
            lookups > 0 ? static_cast<double>(sum.cache_hits) / static_cast<double>(lookups) : -1.0,
            static_cast<double>(sum.fetch_requests),
            static_cast<double>(sum.events)};
}

// A frame's value of every metric column: the machine's, then its kernel's; none where the frame has
// no such figure (no polygons to rate, say).
std::vector<std::optional<double>> frame_values(const RecordedScenario& recording, std::size_t frame,
                                                const FrameTiming& timing, const MachineConfig& config,
                                                const std::vector<SweepColumn>& columns,
                                                const std::set<std::string>& kernel_metrics) {
    const std::vector<double> machine = machine_values(timing, config);
    std::vector<std::optional<double>> values;
    for (std::size_t c = 0; c < columns.size(); ++c) {
        std::optional<double> v;
        if (c < machine.size()) {
            if (machine[c] >= 0) v = machine[c];
        } else if (kernel_metrics.count(columns[c].name)) {
            try {
                v = recording.metric(columns[c].name, frame, timing);
            } catch (const std::domain_error&) {}
        }
        values.push_back(v);
    }
    return values;
}

// The point of a group whose varied values sit nearest the middle of each key's values: where its
// uncertainty is measured, so that every shard measures it at the same point.
std::size_t middle_point(const std::vector<SweepPoint>& plan, const std::vector<std::size_t>& members) {
    std::map<std::string, std::vector<std::string>> values;  // key -> distinct values in plan order
    for (const std::size_t m : members)
        for (const auto& [key, value] : plan[m].parameters) {
            std::vector<std::string>& seen = values[key];
            if (std::find(seen.begin(), seen.end(), value) == seen.end()) seen.push_back(value);
        }
    std::size_t best = members.front();
    double best_distance = INFINITY;
    for (const std::size_t m : members) {
        double distance = 0.0;
        for (const auto& [key, value] : plan[m].parameters) {
            const std::vector<std::string>& seen = values[key];
            const auto rank = static_cast<double>(std::find(seen.begin(), seen.end(), value) - seen.begin());
            distance += std::abs(rank - static_cast<double>(seen.size() - 1) / 2.0);
        }
        if (distance < best_distance) best = m, best_distance = distance;
    }
    return best;
}

// Every metric but a count gets a band (a count of events or fetches is not what the guesses move).
std::vector<std::size_t> banded_columns(const std::vector<SweepColumn>& metrics) {
    std::vector<std::size_t> banded;
    for (std::size_t c = 0; c < metrics.size(); ++c)
        if (metrics[c].unit != "count") banded.push_back(c);
    return banded;
}

// One recording group's uncertainty, measured at its middle point (to be carried to the others): its
// figures are every frame's banded columns, frame by frame.
UncertaintyTable measure_group_bands(const RecordedScenario& recording, const MachineConfig& reference,
                                     const std::vector<SweepColumn>& metrics, const std::vector<std::size_t>& banded,
                                     const std::set<std::string>& kernel_metrics, const std::set<std::string>& varied) {
    const FigureEvaluator figures = [&](const MachineConfig& config) {
        std::vector<double> out;
        const std::vector<FrameTiming> timings = recording.time_on(config);
        for (std::size_t f = 0; f < timings.size(); ++f) {
            const std::vector<std::optional<double>> values =
                frame_values(recording, f, timings[f], config, metrics, kernel_metrics);
            for (const std::size_t c : banded) out.push_back(values[c].value_or(NAN));
        }
        return out;
    };
    return measure_uncertainty(reference, uncertain_parameters(reference, {&recording.kernel()}, varied), figures);
}

// Appends each banded column's low and high ends to a frame's values.
// Without a table (its middle point refused), the ends are left empty.
void add_bands(std::vector<std::optional<double>>& values, const std::vector<std::size_t>& banded,
               const std::optional<UncertaintyTable>& bands, std::size_t frame) {
    for (std::size_t b = 0; b < banded.size(); ++b) {
        const std::optional<double> value = values[banded[b]];
        const std::size_t figure = frame * banded.size() + b;
        std::optional<double> low, high;
        if (bands && value && figure < bands->base.size() && std::isfinite(bands->base[figure])) {
            const Band band = pp5::band(*bands, figure, *value);
            if (std::isfinite(band.low) && std::isfinite(band.high)) low = band.low, high = band.high;
        }
        values.push_back(low);
        values.push_back(high);
    }
}

// The machine's overrides at a point (the kernel is not one of them).
std::vector<std::string> overrides_of(const SweepSpec& spec, const SweepAssignment& parameters, bool timing_too) {
    std::vector<std::string> out = spec.fixed;
    for (const auto& [key, value] : parameters)
        if (key != kSweepKernelKey && (timing_too || !is_timing_parameter(key))) out.push_back(key + "=" + value);
    return out;
}

// The kernel that renders a point: the one it varies to, else its scenario's own.
std::string kernel_at(const SweepAssignment& parameters, const std::string& scenario_kernel) {
    for (const auto& [key, value] : parameters)
        if (key == kSweepKernelKey) return value;
    return scenario_kernel;
}

nlohmann::json parameter_values(const MachineConfig& config) {
    const nlohmann::json all = config.to_json();
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, entry] : all["parameters"].items()) out[key] = entry["value"];
    return out;
}

const char* env(const char* name) {
    const char* v = std::getenv(name);
    return v != nullptr && *v != '\0' ? v : nullptr;
}

std::size_t env_number(const char* name, const char* launcher) {
    const char* text = env(name);
    char* end = nullptr;
    const unsigned long long n = std::strtoull(text, &end, 10);
    if (end == text || *end != '\0' || n > 1000000)
        throw InputError("environment", name, fmt::format("\"{}\" is not a whole number ({})", text, launcher));
    return static_cast<std::size_t>(n);
}

}  // namespace

std::vector<SweepPoint> plan_sweep(const SweepSpec& spec) {
    std::vector<SweepAssignment> combinations;
    if (!spec.axes.empty()) {
        combinations.emplace_back();
        for (const SweepAxis& axis : spec.axes) {
            std::vector<SweepAssignment> next;
            for (const SweepAssignment& partial : combinations)
                for (const std::string& value : axis.values) {
                    SweepAssignment a = partial;
                    a.emplace_back(axis.key, value);
                    next.push_back(std::move(a));
                }
            combinations = std::move(next);
        }
    }
    for (const SweepAssignment& p : spec.points) combinations.push_back(p);
    std::vector<SweepPoint> points;
    for (const std::string& scenario : spec.scenarios)
        for (const SweepAssignment& a : combinations) points.push_back({points.size(), scenario, a});
    return points;
}

Shard parse_shard(const std::string& text) {
    const auto fail = [&] {
        throw InputError("--shard", "--shard", "\"" + text + "\": expected K/N with 0 <= K < N (e.g. 0/4)");
    };
    const auto slash = text.find('/');
    if (slash == std::string::npos) fail();
    const auto number = [&](const std::string& part) {
        if (part.empty() || part.size() > 7 || part.find_first_not_of("0123456789") != std::string::npos) fail();
        return static_cast<std::size_t>(std::stoul(part));
    };
    const Shard shard{number(text.substr(0, slash)), number(text.substr(slash + 1))};
    if (shard.count == 0 || shard.index >= shard.count) fail();
    return shard;
}

std::optional<Shard> shard_from_environment() {
    const auto from = [](const char* rank, const char* size, const char* launcher) -> std::optional<Shard> {
        if (env(rank) == nullptr || env(size) == nullptr) return std::nullopt;
        const Shard s{env_number(rank, launcher), env_number(size, launcher)};
        if (s.count == 0 || s.index >= s.count)
            throw InputError("environment", rank,
                             fmt::format("{} of {} is not a shard ({})", s.index, s.count, launcher));
        return s;
    };
    if (auto s = from("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "Open MPI's mpirun")) return s;
    if (auto s = from("PMI_RANK", "PMI_SIZE", "an MPI launcher")) return s;
    if (env("SLURM_ARRAY_TASK_ID") != nullptr && env("SLURM_ARRAY_TASK_COUNT") != nullptr) {
        const std::size_t id = env_number("SLURM_ARRAY_TASK_ID", "a Slurm array");
        const std::size_t first = env("SLURM_ARRAY_TASK_MIN") ? env_number("SLURM_ARRAY_TASK_MIN", "a Slurm array") : 0;
        const Shard s{id - std::min(id, first), env_number("SLURM_ARRAY_TASK_COUNT", "a Slurm array")};
        if (id < first || s.count == 0 || s.index >= s.count)
            throw InputError("environment", "SLURM_ARRAY_TASK_ID",
                             fmt::format("task {} is not one of {} from {} (use --array=0-{} or --shard)", id, s.count,
                                         first, s.count - 1));
        return s;
    }
    return std::nullopt;
}

namespace {

// One sweep run by one process: its columns and header, then its points, group by group (the points
// that compute the same thing: the scenario, its kernel and the functional overrides), one recording
// each, re-timed at every point of the group this shard takes.
class SweepRunner {
public:
    SweepRunner(const SweepSpec& spec, const Shard& shard, const SweepProgress& progress)
        : spec_(spec), shard_(shard), progress_(progress), plan_(plan_sweep(spec)) {}

    SweepResult run() {
        load_scenarios();
        choose_columns();
        write_header();
        group_points();
        if (spec_.uncertainty) choose_band_points();
        for (const auto& [key, members] : groups_) total_ += members.size();
        for (const auto& group : groups_) run_group(group.first, group.second);
        for (auto& [index, r] : done_) result_.points.push_back(std::move(r));
        return std::move(result_);
    }

private:
    struct Group {
        std::string scenario;
        std::string kernel;
        std::vector<std::string> overrides;  // the functional ones
        auto operator<=>(const Group&) const = default;
    };

    void load_scenarios() {
        for (const std::string& name : spec_.scenarios) {
            Scenario s = load_scenario(resolve_scenario_file(name));
            kernel_of_[name] = &kernel_for(s);
            scenarios_.emplace(name, std::move(s));
        }
    }

    // The columns: the machine's, then each kernel's metrics in the order the scenarios name them, then
    // those of the kernels the sweep varies to; with bands, each banded metric's low and high ends.
    void choose_columns() {
        result_.columns = machine_columns();
        const auto add_metrics_of = [&](const Kernel& kernel) {
            for (const KernelMetric& m : kernel.metrics())
                if (std::none_of(result_.columns.begin(), result_.columns.end(),
                                 [&](const SweepColumn& c) { return c.name == m.name; }))
                    result_.columns.push_back({m.name, m.unit, m.description});
        };
        for (const std::string& name : spec_.scenarios) add_metrics_of(*kernel_of_.at(name));
        for (const SweepPoint& p : plan_)
            if (const std::string k = kernel_at(p.parameters, ""); !k.empty()) add_metrics_of(*find_kernel(k));
        metric_columns_ = result_.columns;
        banded_ = banded_columns(metric_columns_);
        if (spec_.uncertainty)
            for (const std::size_t c : banded_) {
                const SweepColumn& m = metric_columns_[c];
                result_.columns.push_back(
                    {m.name + "_low", m.unit,
                     "low end of " + m.name + "'s 95% band over the documented guesses' plausible ranges"});
                result_.columns.push_back(
                    {m.name + "_high", m.unit,
                     "high end of " + m.name + "'s 95% band over the documented guesses' plausible ranges"});
            }
        if (!spec_.plot_metric.empty() &&
            std::none_of(result_.columns.begin(), result_.columns.end(),
                         [&](const SweepColumn& c) { return c.name == spec_.plot_metric; })) {
            std::string known;
            for (const SweepColumn& c : result_.columns) known += (known.empty() ? "" : ", ") + c.name;
            throw InputError(spec_.file, "sweep.plot_metric",
                             "\"" + spec_.plot_metric + "\" is not a metric of this sweep; known: " + known);
        }
    }

    void write_header() {
        nlohmann::json axes = nlohmann::json::array();
        for (const SweepAxis& a : spec_.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
        nlohmann::json explicit_points = nlohmann::json::array();
        for (const SweepAssignment& p : spec_.points) {
            nlohmann::json point = nlohmann::json::object();
            for (const auto& [k, v] : p) point[k] = v;
            explicit_points.push_back(point);
        }
        result_.header = {{"name", spec_.name},
                          {"description", spec_.description},
                          {"scenarios", spec_.scenarios},
                          {"machine", spec_.machine},
                          {"set", spec_.fixed},
                          {"frames", spec_.frames},
                          {"axes", axes},
                          {"points", explicit_points},
                          {"total_points", plan_.size()},
                          {"plot_x", spec_.plot_x},
                          {"plot_metric", spec_.plot_metric}};
        nlohmann::json kernels = nlohmann::json::object();
        for (const auto& [name, kernel] : kernel_of_) kernels[name] = kernel->name();
        result_.header["kernels"] = kernels;
    }

    // Every point's group, and the groups of the points this shard takes.
    void group_points() {
        for (const SweepPoint& p : plan_) {
            const Group key{p.scenario, kernel_at(p.parameters, kernel_of_.at(p.scenario)->name()),
                            overrides_of(spec_, p.parameters, false)};
            all_groups_[key].push_back(p.index);
            if (shard_.takes(p.index)) groups_[key].push_back(p.index);
            for (const auto& [k, v] : p.parameters) varied_.insert(k);
        }
    }

    // Each group's uncertainty is measured at its middle point, whichever shard runs it.
    void choose_band_points() {
        nlohmann::json references = nlohmann::json::array();
        for (const auto& [key, members] : all_groups_) {
            band_point_of_[key] = middle_point(plan_, members);
            references.push_back(band_point_of_[key]);
        }
        result_.header["uncertainty"] = {
            {"bands",
             "95%, every documented guess (`pp5sim params`, plausible) spread evenly over its range, independently; "
             "the "
             "response to each measured by re-timing with it at either end of its range, at the point below of each "
             "recording group, and carried to the group's other points as a relative change"},
            {"measured_at_points", references},
            {"not_guessed", varied_}};
    }

    // The group's recording, or the reason it has none (a machine that refuses its functional overrides).
    std::unique_ptr<RecordedScenario> record_group(const Group& key, const Scenario& scenario, std::string& error) {
        const int frames = spec_.frames > 0 ? std::min<int>(spec_.frames, static_cast<int>(scenario.frames.size()))
                                            : static_cast<int>(scenario.frames.size());
        try {
            MachineConfig functional = load_run_config(spec_.machine, key.overrides);
            // A lone processor is timed from work recorded on Pixel-planes 5.
            if (functional.machine_kind() == MachineKind::Uniprocessor)
                functional = load_run_config("pxpl5", key.overrides);
            return std::make_unique<RecordedScenario>(scenario, functional, frames);
        } catch (const InputError& e) {
            error = e.what();
            return nullptr;
        }
    }

    std::optional<UncertaintyTable> measure_bands(const Group& key, const RecordedScenario& recording,
                                                  const std::set<std::string>& kernel_metrics) {
        const auto started = std::chrono::steady_clock::now();
        std::optional<UncertaintyTable> bands;
        const SweepPoint& middle = plan_[band_point_of_.at(key)];
        try {
            bands = measure_group_bands(recording,
                                        load_run_config(spec_.machine, overrides_of(spec_, middle.parameters, true)),
                                        metric_columns_, banded_, kernel_metrics, varied_);
            result_.uncertainty_retimings += bands->retimings;
        } catch (const InputError&) {
            // The middle point is one the machine refuses: its row says why, and the group has no bands.
        }
        result_.uncertainty_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        return bands;
    }

    void run_group(const Group& key, const std::vector<std::size_t>& members) {
        Scenario scenario = scenarios_.at(key.scenario);
        scenario.kernel = key.kernel;
        std::set<std::string> kernel_metrics;
        for (const KernelMetric& m : find_kernel(scenario.kernel)->metrics()) kernel_metrics.insert(m.name);
        std::string group_error;
        const std::unique_ptr<RecordedScenario> recording = record_group(key, scenario, group_error);
        std::optional<UncertaintyTable> bands;
        if (recording && spec_.uncertainty) bands = measure_bands(key, *recording, kernel_metrics);
        pp5::parallel_for(std::size_t{0}, members.size(), [&](std::size_t m) {
            const SweepPoint& point = plan_[members[m]];
            SweepPointResult r{point, group_error, nlohmann::json::object(), {}};
            const MachineConfig config = load_run_config(spec_.machine, overrides_of(spec_, point.parameters, true));
            r.parameters = parameter_values(config);
            r.parameters[kSweepKernelKey] = scenario.kernel;
            if (recording) time_point(*recording, config, kernel_metrics, bands, r);
            finish(std::move(r));
        });
    }

    // Every frame of the recording timed on the point's machine (none, with the reason, if it refuses).
    void time_point(const RecordedScenario& recording, const MachineConfig& config,
                    const std::set<std::string>& kernel_metrics, const std::optional<UncertaintyTable>& bands,
                    SweepPointResult& r) const {
        try {
            const std::vector<FrameTiming> timings = recording.time_on(config);
            for (std::size_t f = 0; f < timings.size(); ++f) {
                SweepFrameResult row{f, recording.frames()[f].label,
                                     frame_values(recording, f, timings[f], config, metric_columns_, kernel_metrics)};
                if (spec_.uncertainty) add_bands(row.values, banded_, bands, f);
                r.frames.push_back(std::move(row));
            }
        } catch (const InputError& e) {
            r.error = e.what();
            r.frames.clear();
        }
    }

    void finish(SweepPointResult r) {
        const std::lock_guard<std::mutex> lock(report_);
        const std::size_t index = r.point.index;
        done_.emplace(index, std::move(r));
        ++finished_;
        if (progress_) progress_(finished_, total_);
    }

    const SweepSpec& spec_;
    const Shard& shard_;
    const SweepProgress& progress_;
    const std::vector<SweepPoint> plan_;
    SweepResult result_;
    std::map<std::string, const Kernel*> kernel_of_;  // scenario -> its own kernel
    std::map<std::string, Scenario> scenarios_;
    std::vector<SweepColumn> metric_columns_;
    std::vector<std::size_t> banded_;
    std::map<Group, std::vector<std::size_t>> all_groups_, groups_;
    std::map<Group, std::size_t> band_point_of_;
    std::set<std::string> varied_;  // the sweep's own keys: chosen, not guessed
    std::map<std::size_t, SweepPointResult> done_;
    std::size_t finished_ = 0, total_ = 0;
    std::mutex report_;
};

}  // namespace

SweepResult run_sweep(const SweepSpec& spec, const Shard& shard, const SweepProgress& progress) {
    return SweepRunner(spec, shard, progress).run();
}

}  // namespace pp5
