// Wilson's hybrid kernel on the MR head (wilson-mr-head: 181x217x181, 512x512): host time to make
// the representation at each of the paper's thresholds (BM_Preprocess, with the point count), host
// time per simulated frame (BM_Frame: the PPs' shading, the GPs' quads and points, every region drawn
// by its twins, timed on Pixel-planes 5) and per re-timing of the recorded work (BM_Retime), and the
// measurement behind the default point path (BM_PointPath: points as GP-composited blocks or as
// renderer primitives, simulated slicing time of each).

#include "calibration/timing_model.h"
#include "kernels/registry/run_config.h"
#include "kernels/wilson/hybrid_volume.h"
#include "scene/scenario/scenario_inputs.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

const pp5::Scenario& mr_head() {
    static const pp5::Scenario scenario = pp5::load_scenario(pp5::resolve_scenario_file("wilson-mr-head"));
    return scenario;
}

void BM_Preprocess(benchmark::State& state) {
    static const pp5::Volume volume = pp5::load_dataset(mr_head());
    pp5::WilsonSettings settings;
    settings.downsample_factor = static_cast<int>(state.range(0));
    settings.error_threshold = pp5::kPaperThresholds.at(static_cast<std::size_t>(state.range(1)));
    std::size_t points = 0;
    for (auto _ : state) points = pp5::HybridVolume::build(volume, settings, true).points().size();
    state.counters["points"] = static_cast<double>(points);
    state.SetLabel("k = " + std::to_string(state.range(0)) + ", threshold 1/" +
                   std::to_string(static_cast<int>(1 / settings.error_threshold + 0.5)));
}
BENCHMARK(BM_Preprocess)->ArgsProduct({{2, 4}, {0, 1, 2, 3, 4}})->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_Frame(benchmark::State& state) {
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {});
    double simulated = 0;
    for (auto _ : state) {
        const pp5::RecordedScenario recorded(mr_head(), config, 1);
        simulated = recorded.metric("frame_seconds", 0, recorded.time_on(config).front());
    }
    state.counters["simulated_s"] = simulated;
}
BENCHMARK(BM_Frame)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_Retime(benchmark::State& state) {
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {});
    const pp5::RecordedScenario recorded(mr_head(), config, 1);
    double simulated = 0;
    for (auto _ : state) simulated = pp5::ticks_to_seconds(recorded.time_on(config).front().duration_ps());
    state.counters["simulated_s"] = simulated;
}
BENCHMARK(BM_Retime)->Unit(benchmark::kMillisecond);

void BM_PointPath(benchmark::State& state) {
    const std::string path = state.range(0) == 0 ? "gp_sheets" : "renderer";
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {"wilson.point_path=" + path});
    const pp5::RecordedScenario recorded(mr_head(), config, 1);
    double slicing = 0;
    for (auto _ : state) slicing = recorded.metric("slicing_seconds", 0, recorded.time_on(config).front());
    state.counters["slicing_simulated_s"] = slicing;
    state.SetLabel(path);
}
BENCHMARK(BM_PointPath)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
