// Lim and Shin's claim, measured on this computer: PERM ray casting "at least 200% faster" than
// conventional post-classified ray casting with a distance map. BM_Perm casts the MR head (ch2, the
// mr-head scenario's transfer function and view, D = 5, G = 3 as the paper's Table 2) through the
// structure; BM_Conventional renders the same rays with the reference renderer's interpolate-then-
// shade path (trilinear value and gradient per sample, exact empty-space leaping over 4^3 blocks, the
// distance-map method's equivalent). Both on one thread, at 128^2, 256^2 and 512^2, parallel and
// perspective. BM_Build times the structure's construction (the paper's preprocessing).

#include "kernels/perm/perm_ray_caster.h"
#include "scene/reference/gradient_field.h"
#include "scene/reference/post_classified.h"
#include "scene/scenario/scenario_inputs.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

namespace {

struct Scene {
    pp5::Scenario scenario;
    pp5::Volume volume;
    pp5::GradientField gradients;
    pp5::PermSettings settings;
    std::unique_ptr<pp5::PermStructure> perm;
};

Scene& scene() {
    static Scene s = [] {
        Scene out;
        out.scenario = pp5::load_scenario(pp5::resolve_scenario_file("mr-head"));
        out.volume = pp5::load_dataset(out.scenario);
        out.gradients = pp5::compute_gradients(out.volume);
        out.settings.density_positions = 5;
        out.settings.gradient_positions = 3;
        out.perm = std::make_unique<pp5::PermStructure>(
            pp5::PermStructure::build(out.volume, out.scenario.frames.front().classification, out.settings));
        return out;
    }();
    return s;
}

pp5::Camera camera(bool perspective) {
    pp5::FrameSpec frame = scene().scenario.frames.front();
    frame.camera.projection = perspective ? pp5::Projection::Perspective : pp5::Projection::Parallel;
    return pp5::frame_camera(frame, scene().volume);
}

void BM_Perm(benchmark::State& state) {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    Scene& s = scene();
    const pp5::PermRayCaster caster(*s.perm, s.volume.spacing(), s.settings, {});
    const int size = static_cast<int>(state.range(0));
    const pp5::FrameSpec& f = s.scenario.frames.front();
    const pp5::Camera cam = camera(state.range(1) != 0);
    for (auto _ : state)
        benchmark::DoNotOptimize(
            caster.cast(f.classification, f.colors, f.lighting, cam, {size, size, 1.0f, 0.95f, glm::vec3(0.0f)}));
    state.SetLabel(state.range(1) ? "perspective" : "parallel");
}
BENCHMARK(BM_Perm)->ArgsProduct({{128, 256, 512}, {0, 1}})->Unit(benchmark::kMillisecond);

void BM_Conventional(benchmark::State& state) {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    Scene& s = scene();
    const int size = static_cast<int>(state.range(0));
    const pp5::FrameSpec& f = s.scenario.frames.front();
    const pp5::Camera cam = camera(state.range(1) != 0);
    pp5::CompositeSettings settings;
    settings.width = settings.height = size;
    for (auto _ : state)
        benchmark::DoNotOptimize(
            pp5::render_post_classified(s.volume, s.gradients, f.classification, f.colors, f.lighting, cam, settings));
    state.SetLabel(state.range(1) ? "perspective" : "parallel");
}
BENCHMARK(BM_Conventional)->ArgsProduct({{128, 256, 512}, {0, 1}})->Unit(benchmark::kMillisecond);

void BM_Build(benchmark::State& state) {
    Scene& s = scene();
    pp5::PermSettings settings = s.settings;
    settings.density_positions = static_cast<int>(state.range(0));
    settings.gradient_positions = static_cast<int>(state.range(1));
    std::uint64_t candidates = 0;
    for (auto _ : state)
        candidates =
            pp5::PermStructure::build(s.volume, s.scenario.frames.front().classification, settings).candidates();
    state.counters["candidates"] = static_cast<double>(candidates);
}
BENCHMARK(BM_Build)->Args({5, 3})->Args({3, 3})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
