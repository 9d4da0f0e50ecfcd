#include "calibration/timing_model.h"

#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"
#include "sim/timing/frame_engine.h"
#include "sim/timing/one_processor.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace pp5 {

MachineConfig recording_machine(const TargetSet& targets) {
    std::optional<MachineConfig> first;
    for (const Target& t : targets.targets) {
        if (t.is_formula()) continue;
        MachineConfig config = load_run_config(t.machine, {});
        if (config.machine_kind() == MachineKind::Multicomputer) return config;
        if (!first) first = std::move(config);
    }
    if (!first) throw std::logic_error("recording_machine: the targets simulate nothing");
    return *first;
}

bool is_timing_parameter(const std::string& key) {
    // Every machine and kernel parameter, each declaring whether it only changes timing.
    static const MachineConfig declared(run_param_groups());
    const ParamSpec* spec = declared.find_spec(key);
    return spec != nullptr && spec->timing_only;
}

RecordedScenario::RecordedScenario(const Scenario& scenario, const MachineConfig& functional, int frames)
    : scenario_(scenario), kernel_(kernel_for(scenario)), functional_(functional) {
    kernel_.check(scenario_);
    const Volume volume = load_dataset(scenario_);
    Machine machine(functional);
    const std::unique_ptr<KernelRun> run =
        naming_parameter_origins(functional, [&] { return kernel_.start(machine, functional, scenario_, volume); });
    const int count = std::min(frames, static_cast<int>(scenario_.frames.size()));
    for (int i = 0; i < count; ++i) {
        const FrameSpec& spec = scenario_.frames[static_cast<std::size_t>(i)];
        RecordedFrame recorded{
            spec.label, naming_parameter_origins(functional, [&] { return run->record_frame(spec); }), {}, {}};
        recorded.crude_image = recorded.frame->pass_images.front();
        recorded.refined_image = recorded.frame->pass_images.back();
        recorded.frame->pass_images.clear();  // kept once, above
        frames_.push_back(std::move(recorded));
    }
}

double RecordedScenario::metric(const std::string& name, std::size_t frame, const FrameTiming& timing) const {
    return kernel_.metric(name, *frames_.at(frame).frame, timing);
}

std::vector<FrameTiming> RecordedScenario::time_on(const MachineConfig& machine, std::size_t frames) const {
    frames = std::min(frames, frames_.size());
    check_only_timing_differs(functional_, machine,
                              "calibration only re-times recorded work (render the scenario on that machine instead)");
    std::vector<const FrameWork*> work;
    for (std::size_t i = 0; i < frames; ++i) work.push_back(&frames_[i].frame->work);
    return time_recorded_work(machine, work);
}

void check_only_timing_differs(const MachineConfig& recorded, const MachineConfig& timing, const std::string& remedy) {
    // Called before every re-timing (a fit makes thousands): only the values that differ are looked at.
    for (const std::string& key : timing.keys_differing_from(recorded))
        if (!is_timing_parameter(key))
            throw InputError(
                timing.origin(key), key,
                fmt::format(
                    "is {} but the work was recorded with {}: it changes what the kernels compute, not only how "
                    "long it takes; {}",
                    format_param_value(timing.value(key)), format_param_value(recorded.value(key)), remedy));
}

std::vector<FrameTiming> time_recorded_work(const MachineConfig& machine, const std::vector<const FrameWork*>& work) {
    std::vector<FrameTiming> times;
    if (machine.machine_kind() == MachineKind::Uniprocessor) {
        for (const FrameWork* w : work) times.push_back(time_frame_on_one_processor(machine, *w));
        return times;
    }
    Machine timed(machine);
    for (const FrameWork* w : work) times.push_back(time_frame(timed, *w));
    return times;
}

CalibrationModel::CalibrationModel(const TargetSet& targets, std::optional<MachineConfig> functional,
                                   std::vector<WorkloadSetting> workload,
                                   const std::function<void(const std::string&)>& progress)
    : targets_(targets), workload_(std::move(workload)) {
    const auto with_workload = [&](MachineConfig config) {
        for (const WorkloadSetting& w : workload_) config.set(w.key, w.param_value(), "workload step");
        return config;
    };
    std::map<std::string, int> frames_needed;
    for (const Target& t : targets_.targets) {
        if (t.is_formula()) continue;  // computed, not rendered
        frames_needed[t.scenario] = std::max({frames_needed[t.scenario], t.frame + 1, t.divided_by_frame + 1});
        if (!machines_.count(t.machine)) machines_.emplace(t.machine, with_workload(load_run_config(t.machine, {})));
    }
    if (frames_needed.empty()) return;  // only formula rows: nothing to record (nor to picture)
    for (const Figure& f : targets_.figures)
        frames_needed[f.scenario] = std::max(frames_needed[f.scenario], f.frame + 1);
    const MachineConfig recording = with_workload(functional ? *functional : recording_machine(targets_));
    for (const auto& [name, frames] : frames_needed) {
        const Scenario scenario = load_scenario(resolve_scenario_file(name));
        if (progress) progress(fmt::format("recording {} ({} frame{})", name, frames, frames == 1 ? "" : "s"));
        scenarios_.emplace(name, std::make_unique<RecordedScenario>(scenario, recording, frames));
    }
}

double CalibrationModel::formula_value(const Target& t) const {
    const Kernel* kernel = find_kernel(t.kernel);
    if (kernel == nullptr) throw std::logic_error("CalibrationModel: unknown kernel " + t.kernel);
    try {
        return kernel->formula(t.formula, t.inputs);
    } catch (const std::domain_error& e) {
        throw InputError(targets_.file.string(), "target \"" + t.id + "\" inputs", e.what());
    }
}

const MachineConfig& CalibrationModel::base_config(const std::string& machine) const {
    const auto it = machines_.find(machine);
    if (it == machines_.end()) throw std::logic_error("CalibrationModel: no target runs on machine " + machine);
    return it->second;
}

MachineConfig CalibrationModel::machine_config(const std::string& machine, const CalibrationScales& scales) const {
    MachineConfig config = base_config(machine);
    config.set("calibration.gp_flops_scale", scales.gp_flops, "fit");
    config.set("calibration.gp_cycles_scale", scales.gp_cycles, "fit");
    config.set("calibration.pp_cycles_scale", scales.pp_cycles, "fit");
    return config;
}

const RecordedScenario& CalibrationModel::recording(const std::string& scenario) const {
    const auto it = scenarios_.find(scenario);
    if (it == scenarios_.end()) throw std::logic_error("CalibrationModel: scenario not recorded: " + scenario);
    return *it->second;
}

std::vector<double> CalibrationModel::simulate(const std::string& machine, const CalibrationScales& scales,
                                               const std::vector<const Target*>& targets) const {
    return simulate_on(machine_config(machine, scales), targets);
}

std::vector<double> CalibrationModel::simulate_on(const MachineConfig& config,
                                                  const std::vector<const Target*>& targets) const {
    // Each scenario timed once per call, up to the last frame these targets read.
    std::map<std::string, std::size_t> frames_read;
    for (const Target* t : targets)
        frames_read[t->scenario] = std::max({frames_read[t->scenario], static_cast<std::size_t>(t->frame) + 1,
                                             static_cast<std::size_t>(std::max(t->divided_by_frame, 0)) + 1});
    std::map<std::string, std::vector<FrameTiming>> timed;
    std::vector<double> values;
    for (const Target* t : targets) {
        auto it = timed.find(t->scenario);
        if (it == timed.end())
            it = timed.emplace(t->scenario, recording(t->scenario).time_on(config, frames_read.at(t->scenario))).first;
        const auto frame = static_cast<std::size_t>(t->frame);
        try {
            double value = recording(t->scenario).metric(t->metric, frame, it->second[frame]);
            if (t->divided_by_frame >= 0) {
                const auto by = static_cast<std::size_t>(t->divided_by_frame);
                value /= recording(t->scenario).metric(t->metric, by, it->second[by]);
            }
            values.push_back(value);
        } catch (const std::domain_error& e) {
            throw InputError(targets_.file.string(), "target \"" + t->id + "\" metric", e.what());
        }
    }
    return values;
}

}  // namespace pp5
