#pragma once
// Internal to the reference renderer: the compositor's loop over pixels and samples (composite.h
// states the rules), parametrised by a hook called before a sample reads the eight voxels of a cell,
// which lets voxels be shaded on demand (on_demand_shading.h). composite() passes a hook that does
// nothing.

#include "scene/reference/composite.h"
#include "scene/reference/pixel_tiles.h"
#include "scene/reference/ray_march.h"
#include "scene/reference/trilinear.h"
#include "scene/render/front_to_back.h"

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
    if (volume.rgba.size() !=
        static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z)) {
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
    const float stop_at = settings.early_termination ? settings.termination_opacity : 2.0f;  // 2: never

    Image image(settings.width, settings.height);
    const CompositeStats total =
        for_each_pixel_tiled<CompositeStats>(image, [&](int px, int py, CompositeStats& counters) {
            ++counters.rays;
            FrontToBack ray_color(settings.sample_step, stop_at);
            if (const auto ray = clip_to_volume(rays.ray(px, py), frame)) {
                ++counters.rays_hit;
                const MarchCounts marched = march(*ray, skip, [&](int, glm::vec3 position) {
                    const Cell cell = grid.cell(position);
                    before_cell(cell.corner);
                    const glm::vec4 s = grid.interpolate_rgba(cell, rgba);
                    return ray_color.add(glm::vec3(s), s.a);
                });
                tally(counters, marched);
            }
            return ray_color.over(settings.background);
        });
    if (stats != nullptr) *stats = total;
    return image;
}

}  // namespace pp5::detail
