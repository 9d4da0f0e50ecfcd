// Host time to simulate Levoy's classification and shading pass on the renderers' pixel processors:
// a 256^3 volume (the layered head phantom, so no download is needed; the PPs' time does not depend
// on the data) on the default pxpl5 machine, both programs per iteration. Counters give the simulated
// time and each program's cycles per voxel slot. Target (issue 3): under 1 s of host time a pass.
//
// Argument: host threads.
//
// BM_KeyLightReshadeWithStationaryLights: a frame that moves only the key light of three (two
// stationary), on a 192^3 phantom (256^3 fills the backing store at 64 bits a voxel, leaving no room
// for the kept sum). Argument: levoy.stationary_light_bits (0: every light recomputed at each reshade).

#include "kernels/registry/run_config.h"
#include "kernels/shared/pp_volume/pp_shading.h"
#include "scene/volume/phantoms.h"
#include "sim/machine/machine.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

namespace {

pp5::MachineConfig pxpl5() {
    pp5::MachineConfig config(pp5::run_param_groups());  // the machine's and every kernel's parameters
    config.load_file(pp5::resolve_machine_file("pxpl5"));
    return config;
}

void BM_PpShadingPass256(benchmark::State& state) {
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(0)));
    static const pp5::Volume volume = pp5::make_head_phantom(256);
    const pp5::MachineConfig config = pxpl5();
    pp5::Machine machine(config);
    pp5::PpShading pps(machine, volume, pp5::VoxelStoreSettings::from(config));

    pp5::Classification classification;
    classification.contours = {{40.0f, 0.9f, 1.5f}, {120.0f, 1.0f, 1.0f}};
    const pp5::ColorMap colors{{{0.0f, {0.9f, 0.7f, 0.6f}}, {255.0f, {1.0f, 1.0f, 1.0f}}}};
    pp5::PhongLighting lighting;
    lighting.depth_cue_k2 = 0.5f;
    pp5::ShadingView view;
    view.forward = {0.0f, 0.0f, 1.0f};
    view.center = glm::vec3(127.5f);
    view.radius = 221.0f;

    pp5::PpFrameReport report;
    for (auto _ : state) {
        report = pps.update(classification, colors, lighting, view, true, true);
        benchmark::DoNotOptimize(report);
    }
    state.counters["simulated_ms"] = static_cast<double>(report.duration_ps()) * 1e-9;
    state.counters["classify_ms"] =
        static_cast<double>(report.classification.end_ps - report.classification.start_ps) * 1e-9;
    state.counters["shade_ms"] = static_cast<double>(report.shading.end_ps - report.shading.start_ps) * 1e-9;
    state.counters["classify_slot_cycles"] = static_cast<double>(report.classification.slot_cost.compute_cycles());
    state.counters["shade_slot_cycles"] = static_cast<double>(report.shading.slot_cost.compute_cycles());
    state.counters["slots"] = static_cast<double>(report.shading.slots);
}

void BM_KeyLightReshadeWithStationaryLights(benchmark::State& state) {
    static const pp5::Volume volume = pp5::make_head_phantom(192);
    const pp5::MachineConfig config = pxpl5();
    pp5::Machine machine(config);
    pp5::VoxelStoreSettings store = pp5::VoxelStoreSettings::from(config);
    store.layout.stationary_light_bits = static_cast<int>(state.range(0));
    pp5::PpShading pps(machine, volume, store);

    pp5::Classification classification;
    classification.contours = {{40.0f, 0.9f, 1.5f}};
    const pp5::ColorMap colors{{{0.0f, {0.9f, 0.7f, 0.6f}}, {255.0f, {1.0f, 1.0f, 1.0f}}}};
    pp5::PhongLighting lighting;
    lighting.light_follows_camera = false;
    lighting.specular = 0.0f;
    lighting.light_direction = {0.4f, 1.0f, 0.5f};
    lighting.stationary_lights = {{{-1.0f, 0.6f, 0.2f}, 0.35f}, {{0.0f, 0.3f, 1.0f}, 0.5f}};
    pp5::ShadingView view;
    view.forward = {0.0f, 0.0f, 1.0f};
    view.center = glm::vec3(95.5f);
    view.radius = 166.0f;
    pps.update(classification, colors, lighting, view, true, true);  // stores the stationary sum when kept

    pp5::PpFrameReport report;
    int frame = 0;
    for (auto _ : state) {
        lighting.light_direction.x = (++frame % 2 == 0) ? 0.4f : -0.6f;
        report = pps.update(classification, colors, lighting, view, false, true);
        benchmark::DoNotOptimize(report);
    }
    state.counters["shade_ms"] = static_cast<double>(report.shading.end_ps - report.shading.start_ps) * 1e-9;
    state.counters["shade_slot_cycles"] = static_cast<double>(report.shading.slot_cost.compute_cycles());
    state.counters["stationary_pass_ran"] = report.stationary_lights.ran ? 1.0 : 0.0;
}

}  // namespace

BENCHMARK(BM_KeyLightReshadeWithStationaryLights)->Arg(0)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PpShadingPass256)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
