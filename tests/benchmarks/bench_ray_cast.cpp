// Host time to simulate Levoy's ray casting on the GPs: one 512x512 frame of a 256^3 volume (the
// layered head phantom, so no download is needed) per iteration, the observer turning 5 degrees a
// frame, every pixel cast (refinement complete) or Levoy's adaptive refinement, on the default pxpl5
// machine. Shading is view-independent so that each frame is ray casting alone (the PP passes have
// their own benchmark). Counters: simulated milliseconds per frame and simulated events per host
// second. For comparison, BM_HostCompositor256 times the reference compositor on the same shaded
// volume and views: the target is the simulated frame within 2x of it.
//
// Argument: host threads.

#include "kernels/levoy/levoy_renderer.h"
#include "kernels/registry/run_config.h"
#include "scene/reference/composite.h"
#include "scene/volume/phantoms.h"
#include "sim/machine/machine.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <memory>

namespace {

pp5::MachineConfig pxpl5(const char* threshold) {
    pp5::MachineConfig config(pp5::run_param_groups());  // the machine's and every kernel's parameters
    config.load_file(pp5::resolve_machine_file("pxpl5"));
    config.apply_override(std::string("levoy.refinement_threshold=") + threshold);
    return config;
}

const pp5::Volume& head() {
    static const pp5::Volume volume = pp5::make_head_phantom(256);
    return volume;
}

pp5::LevoyFrameInputs frame_inputs(int index) {
    pp5::LevoyFrameInputs in;
    const glm::vec3 center(127.5f);
    const float angle = glm::radians(30.0f + 5.0f * static_cast<float>(index));
    in.camera.projection = pp5::Projection::Parallel;
    in.camera.eye = center + 700.0f * glm::vec3(std::sin(angle), std::cos(angle), 0.25f);
    in.camera.target = center;
    in.camera.up = {0.0f, 0.0f, 1.0f};
    in.camera.view_height = 300.0f;
    in.classification.contours = {{40.0f, 0.3f, 1.5f}, {160.0f, 0.95f, 1.5f}};
    in.colors = pp5::ColorMap{{{0.0f, {0.9f, 0.7f, 0.6f}}, {220.0f, {1.0f, 1.0f, 0.95f}}}};
    in.lighting.light_follows_camera = false;
    in.lighting.specular = 0.0f;
    in.lighting.light_direction = {0.4f, 1.0f, 0.5f};
    in.classification_changed = index == 0;
    in.lighting_changed = index == 0;
    return in;
}

void ray_cast(benchmark::State& state, const char* threshold) {
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(0)));
    const pp5::MachineConfig config = pxpl5(threshold);
    pp5::Machine machine(config);
    pp5::LevoyRenderer renderer(machine, head(), pp5::LevoySettings::from(config), pp5::LevoyImageSettings{});
    renderer.render(frame_inputs(0));  // shades, builds the pyramid, warms the caches
    int frame = 1;
    double simulated = 0.0;
    double events = 0.0;
    double rays = 0.0;
    double hit_rate = 0.0;
    for (auto _ : state) {
        const pp5::LevoyFrameReport report = renderer.render(frame_inputs(frame++));
        simulated += pp5::ticks_to_seconds(report.duration_ps());
        events += static_cast<double>(report.ray_cast.events);
        rays += static_cast<double>(report.ray_cast.rays);
        const double lookups = static_cast<double>(report.ray_cast.cache_hits + report.ray_cast.cache_misses);
        hit_rate = lookups > 0 ? static_cast<double>(report.ray_cast.cache_hits) / lookups : 0.0;
    }
    const double n = static_cast<double>(state.iterations());
    state.counters["simulated_ms"] = 1e3 * simulated / n;
    state.counters["rays"] = rays / n;
    state.counters["events"] = events / n;
    state.counters["events_per_host_s"] = benchmark::Counter(events, benchmark::Counter::kIsRate);
    state.counters["cache_hit_rate"] = hit_rate;
}

void BM_RayCastFullyRefined256(benchmark::State& state) { ray_cast(state, "-1"); }
void BM_RayCastAdaptive256(benchmark::State& state) { ray_cast(state, "0.1"); }

// The timing engine alone: one fully refined frame recorded once, then replayed on the machine each
// iteration (its GP caches as the frame before left them, so every replay after the first is alike). The
// engine runs on one host thread whatever the thread count, so this is the part of a frame that threads
// do not shorten.
void BM_TimingEngineReplay256(benchmark::State& state) {
    const pp5::MachineConfig config = pxpl5("-1");
    pp5::Machine machine(config);
    pp5::LevoyRenderer renderer(machine, head(), pp5::LevoySettings::from(config), pp5::LevoyImageSettings{});
    renderer.render(frame_inputs(0));
    const pp5::LevoyFrameReport recorded = renderer.record(frame_inputs(1));
    pp5::time_levoy_frame(machine, recorded.work);
    double events = 0.0;
    for (auto _ : state) events += static_cast<double>(pp5::time_levoy_frame(machine, recorded.work).ray_cast.events);
    state.counters["events_per_host_s"] = benchmark::Counter(events, benchmark::Counter::kIsRate);
    state.counters["rays"] = static_cast<double>(recorded.work.rays.rays);
}

void BM_HostCompositor256(benchmark::State& state) {
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(0)));
    const pp5::MachineConfig config = pxpl5("-1");
    pp5::Machine machine(config);
    pp5::LevoyRenderer renderer(machine, head(), pp5::LevoySettings::from(config), pp5::LevoyImageSettings{});
    renderer.render(frame_inputs(0));
    const pp5::OccupancyGrid grid =
        pp5::occupancy_from_alpha(renderer.shaded_volume().dims, renderer.shaded_volume().rgba);
    pp5::CompositeSettings settings;
    int frame = 1;
    for (auto _ : state) {
        const pp5::Image image = pp5::composite(renderer.shaded_volume(), grid, frame_inputs(frame++).camera, settings);
        benchmark::DoNotOptimize(image.pixels.data());
    }
}

}  // namespace

BENCHMARK(BM_RayCastFullyRefined256)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RayCastAdaptive256)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TimingEngineReplay256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_HostCompositor256)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
