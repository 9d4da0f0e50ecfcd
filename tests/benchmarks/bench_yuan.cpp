// Yuan's splatting kernel: host time per simulated frame, and the measurement behind the default
// point path. The scenario is the 100^3 checker box (yuan-checker-box: all 1,000,000 voxels drawn) at
// its three views. BM_Frame records a view (the PPs' shading, the GPs' primitives, every region drawn
// by its twins) and times it on Pixel-planes 5; BM_Retime only re-times the recorded work. BM_PointPath
// times the far view (all points) with the GPs filtering points into sheets and with the renderers
// drawing each point, and reports the simulated splatting time of each.

#include "calibration/timing_model.h"
#include "kernels/registry/run_config.h"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace {

const pp5::Scenario& checker_box() {
    static const pp5::Scenario scenario = pp5::load_scenario(pp5::resolve_scenario_file("yuan-checker-box"));
    return scenario;
}

// One view of the box as a scenario of its own (its frame's camera applied).
pp5::Scenario view(int frame) {
    pp5::Scenario s = checker_box();
    s.frames = {s.frames.at(static_cast<std::size_t>(frame))};
    return s;
}

void BM_Frame(benchmark::State& state) {
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {});
    const pp5::Scenario scenario = view(static_cast<int>(state.range(0)));
    double simulated = 0;
    for (auto _ : state) {
        const pp5::RecordedScenario recorded(scenario, config, 1);
        simulated = recorded.metric("frame_seconds", 0, recorded.time_on(config).front());
    }
    state.counters["simulated_s"] = simulated;
    state.SetLabel(scenario.frames.front().label);
}
BENCHMARK(BM_Frame)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_Retime(benchmark::State& state) {
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {});
    const pp5::RecordedScenario recorded(view(static_cast<int>(state.range(0))), config, 1);
    double simulated = 0;
    for (auto _ : state) simulated = pp5::ticks_to_seconds(recorded.time_on(config).front().duration_ps());
    state.counters["simulated_s"] = simulated;
}
BENCHMARK(BM_Retime)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_PointPath(benchmark::State& state) {
    const std::string path = state.range(1) == 0 ? "gp_sheets" : "renderer";
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {"yuan.point_path=" + path});
    const pp5::RecordedScenario recorded(view(static_cast<int>(state.range(0))), config, 1);
    double splatting = 0;
    for (auto _ : state) splatting = recorded.metric("splatting_seconds", 0, recorded.time_on(config).front());
    state.counters["splatting_simulated_s"] = splatting;
    state.SetLabel(path + (state.range(0) == 2 ? ", far view (all points)" : ", mixed view"));
}
BENCHMARK(BM_PointPath)
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
