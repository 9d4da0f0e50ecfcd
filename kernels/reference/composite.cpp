#include "kernels/reference/composite.h"

#include "kernels/reference/composite_loop.h"
#include "sim/core/input_error.h"

#include <cmath>

namespace pp5 {

namespace {

void fail(const char* field, const char* reason) { throw InputError("", field, reason); }

}  // namespace

void validate_composite_settings(const CompositeSettings& settings) {
    constexpr int kMaxSize = 16384;
    if (settings.width < 1 || settings.width > kMaxSize) fail("render.width", "must lie in [1, 16384]");
    if (settings.height < 1 || settings.height > kMaxSize) fail("render.height", "must lie in [1, 16384]");
    if (!(settings.sample_step >= 1e-3f && std::isfinite(settings.sample_step))) {
        fail("render.sample_step", "must be at least 0.001 voxels and finite");
    }
    if (!(settings.termination_opacity > 0.0f && settings.termination_opacity <= 1.0f)) {
        fail("render.termination_opacity", "must lie in (0, 1]");
    }
    const glm::vec3 bg = settings.background;
    if (!(std::isfinite(bg.r) && std::isfinite(bg.g) && std::isfinite(bg.b))) fail("render.background", "must be finite");
}

CompositeStats& CompositeStats::operator+=(const CompositeStats& other) {
    rays += other.rays;
    rays_hit += other.rays_hit;
    samples += other.samples;
    samples_skipped += other.samples_skipped;
    rays_terminated += other.rays_terminated;
    return *this;
}

Image composite(const ShadedVolume& volume, const Camera& camera, const CompositeSettings& settings,
                CompositeStats* stats) {
    const OccupancyGrid occupancy = settings.skip_empty_space ? occupancy_from_alpha(volume.dims, volume.rgba)
                                                              : OccupancyGrid(volume.dims, /*occupied=*/true);
    return composite(volume, occupancy, camera, settings, stats);
}

Image composite(const ShadedVolume& volume, const OccupancyGrid& occupancy, const Camera& camera,
                const CompositeSettings& settings, CompositeStats* stats) {
    return detail::composite_loop(volume, occupancy, camera, settings, stats, [](glm::ivec3) {});
}

}  // namespace pp5
