#pragma once
// Internal to the reference renderer: the compositor's loop over pixels and samples (composite.h
// states the rules), parametrised by a hook called before a sample reads the eight voxels of a cell,
// which lets voxels be shaded on demand (on_demand_shading.h). composite() passes a hook that does
// nothing.

#include "kernels/reference/composite.h"
#include "kernels/reference/pixel_tiles.h"
#include "kernels/reference/ray_march.h"
#include "kernels/reference/trilinear.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pp5::detail {

// before_cell(glm::ivec3 lower_corner) must make that cell's eight voxels readable in `volume`.
template <class BeforeCell>
Image composite_loop(const ShadedVolume& volume, const OccupancyGrid& occupancy, const Camera& camera,
                     const CompositeSettings& settings, CompositeStats* stats, BeforeCell&& before_cell) {
    validate_camera(camera);
    validate_composite_settings(settings);
    const glm::ivec3 dims = volume.dims;
    if (volume.rgba.size() != static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z)) {
        throw std::invalid_argument("composite: rgba size does not match dims");
    }
    if (settings.skip_empty_space && occupancy.volume_dims() != dims) {
        throw std::invalid_argument("composite: occupancy grid of another volume");
    }

    const MarchFrame frame(dims, volume.spacing, settings.sample_step);
    const Grid grid(dims);
    const PixelRays rays(camera, settings.width, settings.height);
    const OccupancyGrid* skip = settings.skip_empty_space ? &occupancy : nullptr;
    const glm::vec4* rgba = volume.rgba.data();
    const float step = settings.sample_step;
    const bool correct_opacity = step != 1.0f;
    const float stop_at = settings.early_termination ? settings.termination_opacity : 2.0f;  // 2: never

    Image image(settings.width, settings.height);
    const CompositeStats total = for_each_pixel_tiled<CompositeStats>(image, [&](int px, int py, CompositeStats& counters) {
        ++counters.rays;
        glm::vec3 color{0.0f};
        float opacity = 0.0f;
        if (const auto ray = clip_to_volume(rays.ray(px, py), frame)) {
            ++counters.rays_hit;
            const MarchCounts marched = march(*ray, skip, [&](int, glm::vec3 position) {
                const Cell cell = grid.cell(position);
                before_cell(cell.corner);
                const glm::vec4 s = grid.interpolate_rgba(cell, rgba);
                float alpha = std::clamp(s.a, 0.0f, 1.0f);
                if (alpha <= 0.0f) return false;
                if (correct_opacity) alpha = 1.0f - std::pow(1.0f - alpha, step);
                const float weight = (1.0f - opacity) * alpha;
                color += weight * glm::vec3(s);
                opacity += weight;
                return opacity >= stop_at;
            });
            counters.samples += marched.samples;
            counters.samples_skipped += marched.skipped;
            if (marched.terminated) ++counters.rays_terminated;
        }
        return glm::vec4(color + (1.0f - opacity) * settings.background, opacity);
    });
    if (stats != nullptr) *stats = total;
    return image;
}

}  // namespace pp5::detail
