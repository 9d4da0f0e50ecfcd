// The reference renderer on the MR head ch2 (181x217x181, uint8, 1 mm) at 512x512: one frame per
// iteration, the camera turning 5 degrees a frame about the head after a warm-up frame, shaded, one
// sample per voxel step. Reported time is wall-clock per frame. Comparison point (toolchain notes):
// VTK 9.1's CPU fixed-point ray caster, opacity ramp 20->60, 45-50 ms a frame with 2 threads and
// 70-77 ms with 1 on a 2-core machine.
//
// Arguments: threads (tbb::global_control), and for the ramp, the resampling order.

#include "scene/reference/reference_renderer.h"
#include "scene/volume/datasets.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <glm/geometric.hpp>

#include <exception>
#include <memory>
#include <string>

namespace {

// Loaded once; null (with the reason) when the dataset is not installed.
const pp5::Volume* ch2(std::string* why) {
    static std::string error;
    static const std::unique_ptr<pp5::Volume> volume = []() -> std::unique_ptr<pp5::Volume> {
        try {
            return std::make_unique<pp5::Volume>(pp5::load_packaged_dataset("ch2"));
        } catch (const std::exception& e) {
            error = std::string("ch2 unavailable (apt-get install mricron-data): ") + e.what();
            return nullptr;
        }
    }();
    if (why != nullptr) *why = error;
    return volume.get();
}

pp5::ColorMap skin_to_white() { return pp5::ColorMap{{{20.0f, {0.9f, 0.7f, 0.6f}}, {100.0f, {1.0f, 1.0f, 1.0f}}}}; }

// VTK's comparison: scalar opacity 0 at 20 rising to 1 at 60, held above.
pp5::Classification opacity_ramp() {
    pp5::Classification c;
    c.kind = pp5::ClassificationKind::PiecewiseLinear;
    c.points = {{20.0f, 0.0f}, {60.0f, 1.0f}};
    return c;
}

// Levoy's isovalue contours: a translucent skin and an opaque brain surface.
pp5::Classification isovalue_contours() {
    pp5::Classification c;
    c.kind = pp5::ClassificationKind::IsovalueContours;
    c.contours = {{40.0f, 0.4f, 1.5f}, {100.0f, 1.0f, 1.5f}};
    return c;
}

void run_orbit(benchmark::State& state, const pp5::Classification& classification, pp5::ResamplingOrder order) {
    std::string why;
    const pp5::Volume* volume = ch2(&why);
    if (volume == nullptr) {
        state.SkipWithError(why.c_str());
        return;
    }
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(state.range(0)));
    pp5::ReferenceRenderer renderer(*volume);
    renderer.set_classification(classification, skin_to_white());
    renderer.set_lighting(pp5::PhongLighting{});

    pp5::RenderSettings settings;
    settings.width = 512;
    settings.height = 512;
    settings.sample_step = 1.0f;
    settings.resampling = order;

    const glm::vec3 extent = glm::vec3(volume->dims() - 1) * volume->spacing();
    pp5::OrbitView orbit;
    orbit.projection = pp5::Projection::Perspective;
    auto camera_at = [&](float azimuth) {
        orbit.azimuth_degrees = azimuth;
        return pp5::orbit_camera(0.5f * extent, 0.5f * glm::length(extent), orbit);
    };

    float azimuth = 0.0f;
    renderer.render(camera_at(azimuth), settings);  // warm-up: gradients, opacities, first shading

    pp5::RenderStats stats;
    double samples = 0.0;
    double skipped = 0.0;
    double shaded = 0.0;
    double shading_seconds = 0.0;
    for (auto _ : state) {
        azimuth += 5.0f;
        pp5::Image image = renderer.render(camera_at(azimuth), settings, &stats);
        benchmark::DoNotOptimize(image.pixels.data());
        samples += static_cast<double>(stats.composite.samples);
        skipped += static_cast<double>(stats.composite.samples_skipped);
        shaded += static_cast<double>(stats.voxels_shaded);
        shading_seconds += stats.seconds.shading;
    }
    const double frames = static_cast<double>(state.iterations());
    state.counters["samples/frame"] = samples / frames;
    state.counters["skipped/frame"] = skipped / frames;
    state.counters["voxels_shaded/frame"] = shaded / frames;
    state.counters["shading_ms/frame"] = 1e3 * shading_seconds / frames;
}

void BM_Ch2Ramp_ShadeThenInterpolate(benchmark::State& state) {
    run_orbit(state, opacity_ramp(), pp5::ResamplingOrder::ShadeThenInterpolate);
}
void BM_Ch2Isovalues_ShadeThenInterpolate(benchmark::State& state) {
    run_orbit(state, isovalue_contours(), pp5::ResamplingOrder::ShadeThenInterpolate);
}
void BM_Ch2Ramp_InterpolateThenShade(benchmark::State& state) {
    run_orbit(state, opacity_ramp(), pp5::ResamplingOrder::InterpolateThenShade);
}

}  // namespace

BENCHMARK(BM_Ch2Ramp_ShadeThenInterpolate)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ch2Isovalues_ShadeThenInterpolate)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Ch2Ramp_InterpolateThenShade)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
