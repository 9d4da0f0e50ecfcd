// Host time of what a calibration fit repeats: re-timing a scenario's recorded work on a machine with
// other costs, against rendering it again. The scenario is Levoy's MR head sequence (six 512x512
// frames: orbit, light, colour and isovalue changes; needs mricron-data). BM_Render renders and times
// it from scratch; BM_Retime* only re-time the recorded work, on Pixel-planes 5 (event by event) and
// on the Sun 4/280 (a sum). A fit evaluates the model a few dozen times per machine.

#include "calibration/timing_model.h"
#include "kernels/registry/run_config.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace {

const pp5::Scenario& sequence() {
    static const pp5::Scenario scenario = pp5::load_scenario(pp5::resolve_scenario_file("mr-head-sequence"));
    return scenario;
}

const pp5::RecordedScenario& recording() {
    static const std::unique_ptr<pp5::RecordedScenario> recorded =
        std::make_unique<pp5::RecordedScenario>(sequence(), pp5::load_run_config("pxpl5", {}), 6);
    return *recorded;
}

void BM_Render(benchmark::State& state) {
    const pp5::MachineConfig config = pp5::load_run_config("pxpl5", {});
    for (auto _ : state) {
        const pp5::RecordedScenario fresh(sequence(), config, 6);
        benchmark::DoNotOptimize(fresh.frames().size());
    }
    state.SetLabel("6 frames rendered and timed");
}
BENCHMARK(BM_Render)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_RetimePxpl5(benchmark::State& state) {
    const pp5::RecordedScenario& recorded = recording();
    const pp5::MachineConfig config =
        pp5::load_run_config("pxpl5", {"calibration.gp_flops_scale=1.7", "calibration.pp_cycles_scale=0.8"});
    double refined = 0;
    std::uint64_t events = 0;
    for (auto _ : state) {
        const std::vector<pp5::FrameTiming> frames = recorded.time_on(config);
        refined = pp5::ticks_to_seconds(frames.back().duration_ps());
        events = 0;
        for (const pp5::FrameTiming& frame : frames)
            for (const pp5::PhaseTiming& phase : frame.phases) events += phase.gp.events;
    }
    state.counters["last_frame_refined_ms"] = 1e3 * refined;
    // Simulated events (GP phases) per host second: the event core's throughput.
    state.counters["events_per_second"] =
        benchmark::Counter(static_cast<double>(events), benchmark::Counter::kIsIterationInvariantRate);
    state.SetLabel("6 frames re-timed");
}
BENCHMARK(BM_RetimePxpl5)->Unit(benchmark::kMillisecond);

void BM_RetimeSun(benchmark::State& state) {
    const pp5::RecordedScenario& recorded = recording();
    const pp5::MachineConfig config = pp5::load_run_config("sun4-280", {});
    double crude = 0;
    for (auto _ : state) crude = recorded.metric("crude_seconds", 1, recorded.time_on(config)[1]);
    state.counters["orbit_crude_s"] = crude;
}
BENCHMARK(BM_RetimeSun)->Unit(benchmark::kMillisecond);

}  // namespace
