#include "scene/reference/composite.h"

#include "scene/reference/composite_loop.h"
#include "sim/core/input_error.h"

#include <cmath>

namespace pp5 {

void validate_composite_settings(const CompositeSettings& settings) {
    constexpr int kMaxSize = 16384;
    if (settings.width < 1 || settings.width > kMaxSize) reject_field("render.width", "must lie in [1, 16384]");
    if (settings.height < 1 || settings.height > kMaxSize) reject_field("render.height", "must lie in [1, 16384]");
    if (!(settings.sample_step >= 1e-3f && std::isfinite(settings.sample_step))) {
        reject_field("render.sample_step", "must be at least 0.001 voxels and finite");
    }
    if (!(settings.termination_opacity > 0.0f && settings.termination_opacity <= 1.0f)) {
        reject_field("render.termination_opacity", "must lie in (0, 1]");
    }
    const glm::vec3 bg = settings.background;
    if (!(std::isfinite(bg.r) && std::isfinite(bg.g) && std::isfinite(bg.b)))
        reject_field("render.background", "must be finite");
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
