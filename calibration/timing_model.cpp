#include "calibration/timing_model.h"

#include "kernels/levoy/levoy_kernel.h"
#include "kernels/registry/run_config.h"
#include "sim/timing/one_processor.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace pp5 {

namespace {

FrameTimes frame_times(const LevoyFrameTiming& t) {
    FrameTimes times;
    times.crude_seconds = ticks_to_seconds(t.crude_ps());
    times.refined_seconds = ticks_to_seconds(t.refined_ps());
    times.pp_seconds = ticks_to_seconds(t.pixel_processors.duration_ps());
    times.scan_converted = t.geometry.ran;
    times.polygons = static_cast<double>(t.geometry.polygons);
    times.scan_conversion_seconds = ticks_to_seconds(t.geometry.end_ps - t.geometry.start_ps);
    return times;
}

// Only these parameters may differ between the recording machine and the machine that re-times.
constexpr const char* kTimingGroups[] = {"gp.", "gp_cost.", "pp.", "ring.", "calibration."};
constexpr const char* kTimingKeys[] = {"renderer.clock_mhz", "renderer.fetch_setup_cycles", "renderer.fetch_cycles_per_unit"};

}  // namespace

bool is_timing_parameter(const std::string& key) {
    for (const char* group : kTimingGroups)
        if (key.starts_with(group)) return true;
    return std::find(std::begin(kTimingKeys), std::end(kTimingKeys), key) != std::end(kTimingKeys);
}

double metric_value(Metric metric, const FrameTimes& t, const std::string& file, const std::string& field) {
    const auto need_polygons = [&] {
        if (!t.scan_converted || t.polygons == 0.0 || t.scan_conversion_seconds <= 0.0)
            throw InputError(file, field, "the frame scan-converts no polygons, so it has no polygon rate");
    };
    switch (metric) {
        case Metric::CrudeSeconds: return t.crude_seconds;
        case Metric::RefinedSeconds: return t.refined_seconds;
        case Metric::RefinementSeconds: return t.refined_seconds - t.crude_seconds;
        case Metric::PixelProcessorSeconds:
            if (t.pp_seconds <= 0.0) throw InputError(file, field, "the frame runs no classification or shading pass");
            return t.pp_seconds;
        case Metric::PolygonsPerSecond: need_polygons(); return t.polygons / t.scan_conversion_seconds;
        case Metric::SecondsPerPolygon: need_polygons(); return t.scan_conversion_seconds / t.polygons;
        case Metric::SpeedupFor30Hz: return t.crude_seconds * 30.0;
    }
    return 0.0;
}

RecordedScenario::RecordedScenario(const Scenario& scenario, const MachineConfig& functional, int frames)
    : scenario_(scenario), functional_(functional) {
    const Volume volume = load_dataset(scenario);
    Machine machine(functional);
    LevoyRenderer workstation(machine, volume, LevoySettings::from(functional), levoy_image_settings(scenario.image));
    workstation.set_polygons(scenario.polygons);
    const int count = std::min(frames, static_cast<int>(scenario.frames.size()));
    for (int i = 0; i < count; ++i) {
        const FrameSpec& frame = scenario.frames[static_cast<std::size_t>(i)];
        LevoyFrameReport report = workstation.render(levoy_frame_inputs(frame, volume));
        frames_.push_back(RecordedFrame{frame.label, std::move(report.work), std::move(report.passes.front().image),
                                        std::move(report.final_image)});
    }
}

std::vector<FrameTimes> RecordedScenario::time_on(const MachineConfig& machine) const {
    const nlohmann::json recorded = functional_.to_json()["parameters"];
    const nlohmann::json timing = machine.to_json()["parameters"];
    for (const auto& [key, entry] : recorded.items()) {
        if (!is_timing_parameter(key) && timing.contains(key) && timing[key]["value"] != entry["value"]) {
            throw InputError(timing[key]["origin"].get<std::string>(), key,
                             fmt::format("is {} but the work was recorded with {}: it changes what the kernels compute, and "
                                         "calibration only re-times recorded work (render the scenario on that machine instead)",
                                         timing[key]["value"].dump(), entry["value"].dump()));
        }
    }
    std::vector<FrameTimes> times;
    if (machine.machine_kind() == MachineKind::Uniprocessor) {
        for (const RecordedFrame& frame : frames_)
            times.push_back(frame_times(levoy_frame_timing(frame.work, time_frame_on_one_processor(machine, frame.work.machine))));
        return times;
    }
    Machine timed(machine);
    for (const RecordedFrame& frame : frames_) times.push_back(frame_times(time_levoy_frame(timed, frame.work)));
    return times;
}

CalibrationModel::CalibrationModel(const TargetSet& targets, std::optional<MachineConfig> functional) : targets_(targets) {
    std::map<std::string, int> frames_needed;
    std::optional<MachineConfig> first_multicomputer;
    for (const Target& t : targets_.targets) {
        frames_needed[t.scenario] = std::max(frames_needed[t.scenario], t.frame + 1);
        if (!machines_.count(t.machine)) machines_.emplace(t.machine, load_run_config(t.machine, {}));
        if (!first_multicomputer && machines_.at(t.machine).machine_kind() == MachineKind::Multicomputer) first_multicomputer = machines_.at(t.machine);
    }
    // The work is recorded on the first Pixel-planes 5 machine the targets name (every machine must
    // compute the same; time_on checks), or on the first machine when all are uniprocessors.
    const MachineConfig recording =
        functional ? *functional : first_multicomputer ? *first_multicomputer : machines_.at(targets_.targets.front().machine);
    for (const auto& [name, frames] : frames_needed) {
        const Scenario scenario = load_scenario(resolve_scenario_file(name));
        scenarios_.emplace(name, std::make_unique<RecordedScenario>(scenario, recording, frames));
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
    const MachineConfig config = machine_config(machine, scales);
    std::map<std::string, std::vector<FrameTimes>> timed;  // each scenario timed once per call
    std::vector<double> values;
    for (const Target* t : targets) {
        auto it = timed.find(t->scenario);
        if (it == timed.end()) it = timed.emplace(t->scenario, recording(t->scenario).time_on(config)).first;
        values.push_back(metric_value(t->metric, it->second[static_cast<std::size_t>(t->frame)], targets_.file.string(),
                                      "target \"" + t->id + "\" metric"));
    }
    return values;
}

}  // namespace pp5
