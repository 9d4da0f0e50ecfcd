// Host time to simulate Levoy's 3D scan-conversion of a triangle mesh on the renderers: a sphere of
// N triangles (a latitude-longitude tessellation, radius 90 voxels) scan-converted into the 256^3 head
// phantom on the default pxpl5 machine, 16 subvoxel translations. Each iteration renders one frame
// that scan-converts the whole mesh (after its classification and shading, which the N = 0 run times
// alone) and casts a 128 x 128 image. Target (issue 36): 100,000 polygons in under 20 s of host time.
// One host thread, as the issue measured.
//
// Argument: triangles (about; the tessellation rounds them).

#include "kernels/levoy/levoy_renderer.h"
#include "kernels/registry/run_config.h"
#include "scene/volume/phantoms.h"
#include "sim/machine/machine.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

namespace {

// A latitude-longitude sphere of about `triangles` triangles.
std::vector<pp5::PolygonSpec> sphere_mesh(int triangles) {
    const int bands = std::max(2, static_cast<int>(std::sqrt(triangles / 2.0)));
    const auto point = [&](int i, int j) {
        const double theta = M_PI * i / bands, phi = 2.0 * M_PI * j / bands;
        return glm::vec3(128.0) +
               90.0f * glm::vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    };
    std::vector<pp5::PolygonSpec> mesh;
    for (int i = 0; i < bands; ++i)
        for (int j = 0; j < bands; ++j) {
            const glm::vec3 a = point(i, j), b = point(i, j + 1), c = point(i + 1, j), d = point(i + 1, j + 1);
            mesh.push_back({{a, c, b}, {glm::vec3(0.9f, 0.2f, 0.2f)}, {0.9f}});
            mesh.push_back({{b, c, d}, {glm::vec3(0.9f, 0.2f, 0.2f)}, {0.9f}});
        }
    return mesh;
}

void BM_ScanConvertSphere(benchmark::State& state) {
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    static const pp5::Volume volume = pp5::make_head_phantom(256);
    pp5::MachineConfig config(pp5::run_param_groups());
    config.load_file(pp5::resolve_machine_file("pxpl5"));
    pp5::Machine machine(config);
    pp5::LevoyRenderer renderer(machine, volume, pp5::LevoySettings::from(config),
                                pp5::LevoyImageSettings{128, 128, 1.0f, 0.95f, glm::vec3(0.0f)});
    const std::vector<pp5::PolygonSpec> mesh =
        state.range(0) > 0 ? sphere_mesh(static_cast<int>(state.range(0))) : std::vector<pp5::PolygonSpec>{};
    pp5::LevoyFrameInputs in;
    in.camera.eye = glm::vec3(127.5f, -600.0f, 127.5f);
    in.camera.target = glm::vec3(127.5f);
    in.camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
    in.camera.view_height = 300.0f;
    in.classification.contours = {{40.0f, 0.25f, 1.5f}, {160.0f, 0.9f, 1.5f}};
    in.colors = pp5::ColorMap{{{0.0f, {0.9f, 0.7f, 0.6f}}, {220.0f, {1.0f, 1.0f, 0.95f}}}};
    pp5::LevoyFrameReport report;
    for (auto _ : state) {
        renderer.set_polygons(mesh);
        report = renderer.render(in);
        benchmark::DoNotOptimize(report);
    }
    state.counters["triangles"] = static_cast<double>(mesh.size());
    state.counters["slot_runs"] = static_cast<double>(report.geometry.slots);
    state.counters["simulated_geometry_ms"] =
        static_cast<double>(report.geometry.end_ps - report.geometry.start_ps) * 1e-9;
}
BENCHMARK(BM_ScanConvertSphere)->Arg(0)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
