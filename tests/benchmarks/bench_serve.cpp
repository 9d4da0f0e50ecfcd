// Host time for `pp5sim serve` to answer what a class does on the 512x512 MR head (the default
// scenario's volume, Debian's mricron-data): a light move (the PPs reshade, the GPs cast), an orbit
// (the GPs cast), a region move (the PPs reclassify), a change of GP count (a re-time of the recorded frame, no
// rendering), and the PSNR read-out the page asks for after a light move (the reference renderer, deferred). Each
// iteration is one change applied to the interactive view, as the HTTP handler applies it; counters give the changed
// frame's simulated milliseconds.

#include "frontends/serve/interactive_view.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"

#include <benchmark/benchmark.h>

#include <memory>

namespace {

pp5::InteractiveView& view() {
    static const auto made = std::make_unique<pp5::InteractiveView>(
        pp5::load_scenario(pp5::resolve_scenario_file("mr-head")), pp5::load_run_config("pxpl5", {}));
    return *made;
}

double simulated_ms() { return 1e3 * view().state()["frame"]["simulated_seconds"].get<double>(); }

void BM_ServeLightMove(benchmark::State& state) {
    view();  // the first frame is rendered before the clock starts
    int step = 0;
    for (auto _ : state) {
        const double x = (++step % 2 == 0) ? 0.4 : -0.4;
        view().apply({{"light", {{"direction", {x, 1.0, 0.3}}}}});
    }
    state.counters["simulated_ms"] = simulated_ms();
}
BENCHMARK(BM_ServeLightMove)->Unit(benchmark::kMillisecond)->Iterations(6);

void BM_ServeOrbit(benchmark::State& state) {
    view();
    int step = 0;
    for (auto _ : state) view().apply({{"camera", {{"azimuth", 20.0 + 5.0 * (++step % 2)}}}});
    state.counters["simulated_ms"] = simulated_ms();
}
BENCHMARK(BM_ServeOrbit)->Unit(benchmark::kMillisecond)->Iterations(6);

// The region moved by a few voxels, as a drag does: the PPs reclassify inside and outside it, the
// pyramid is rebuilt and the GPs cast.
void BM_ServeRegionMove(benchmark::State& state) {
    view().apply({{"region", nlohmann::json::object()}});  // a cut-away cube in the middle
    int step = 0;
    for (auto _ : state) {
        const double x = (++step % 2 == 0) ? 80.0 : 84.0;
        view().apply({{"region", {{"center", {x, 128.0, 90.0}}}}});
    }
    state.counters["simulated_ms"] = simulated_ms();
    view().apply({{"region", nullptr}});
}
BENCHMARK(BM_ServeRegionMove)->Unit(benchmark::kMillisecond)->Iterations(6);

void BM_ServeRetimeGpCount(benchmark::State& state) {
    view();
    int step = 0;
    for (auto _ : state) view().apply({{"machine", {{"gp.count", (++step % 2 == 0) ? 32 : 16}}}});
    state.counters["simulated_ms"] = simulated_ms();
    view().apply({{"machine", {{"gp.count", 32}}}});
}
BENCHMARK(BM_ServeRetimeGpCount)->Unit(benchmark::kMillisecond)->Iterations(10);

void BM_ServeLightMoveThenPsnr(benchmark::State& state) {
    view();
    int step = 0;
    for (auto _ : state) {
        const double x = (++step % 2 == 0) ? 0.3 : -0.3;
        view().apply({{"light", {{"direction", {x, 1.0, 0.3}}}}});
        benchmark::DoNotOptimize(view().reference_fidelity());
    }
    state.counters["simulated_ms"] = simulated_ms();
}
BENCHMARK(BM_ServeLightMoveThenPsnr)->Unit(benchmark::kMillisecond)->Iterations(6);

}  // namespace
