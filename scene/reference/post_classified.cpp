#include "scene/reference/post_classified.h"

#include "scene/reference/pixel_tiles.h"
#include "scene/reference/ray_march.h"
#include "scene/reference/sample_shader.h"
#include "scene/reference/trilinear.h"
#include "scene/render/front_to_back.h"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <stdexcept>

namespace pp5 {

Image render_post_classified(const Volume& volume, const GradientField& gradients, const Classification& classification,
                             const ColorMap& color_map, const PhongLighting& lighting, const Camera& camera,
                             const CompositeSettings& settings, CompositeStats* stats) {
    const OccupancyGrid occupancy =
        settings.skip_empty_space
            ? occupancy_from_value_ranges(compute_block_value_ranges(volume, gradients), classification)
            : OccupancyGrid(volume.dims(), /*occupied=*/true);
    return render_post_classified(volume, gradients, classification, color_map, lighting, camera, settings, occupancy,
                                  stats);
}

Image render_post_classified(const Volume& volume, const GradientField& gradients, const Classification& classification,
                             const ColorMap& color_map, const PhongLighting& lighting, const Camera& camera,
                             const CompositeSettings& settings, const OccupancyGrid& occupancy, CompositeStats* stats) {
    validate_camera(camera);
    validate_composite_settings(settings);
    const glm::ivec3 dims = volume.dims();
    if (gradients.dims != dims) throw std::invalid_argument("render_post_classified: gradients of another volume");
    if (settings.skip_empty_space && occupancy.volume_dims() != dims) {
        throw std::invalid_argument("render_post_classified: occupancy grid of another volume");
    }

    const glm::vec3 spacing = volume.spacing();
    const detail::MarchFrame frame(dims, spacing, settings.sample_step);
    const detail::Grid grid(dims);
    const PixelRays rays(camera, settings.width, settings.height);
    const SampleShader shader(color_map, lighting, make_shading_view(camera, dims, spacing), spacing);
    const OccupancyGrid* skip = settings.skip_empty_space ? &occupancy : nullptr;
    const float* values = volume.samples().data();
    const glm::vec3* gradient = gradients.gradients.data();
    const float stop_at = settings.early_termination ? settings.termination_opacity : 2.0f;  // 2: never

    Image image(settings.width, settings.height);
    const CompositeStats total =
        detail::for_each_pixel_tiled<CompositeStats>(image, [&](int px, int py, CompositeStats& counters) {
            ++counters.rays;
            FrontToBack ray_color(settings.sample_step, stop_at);
            if (const auto ray = detail::clip_to_volume(rays.ray(px, py), frame)) {
                ++counters.rays_hit;
                const detail::MarchCounts marched = detail::march(*ray, skip, [&](int, glm::vec3 position) {
                    const detail::Cell cell = grid.cell(position);
                    const float value = grid.interpolate<float>(cell, [&](std::size_t i) { return values[i]; });
                    const glm::vec3 g = grid.interpolate<glm::vec3>(cell, [&](std::size_t i) { return gradient[i]; });
                    const float alpha = classification.opacity(value, glm::length(g));
                    if (alpha <= 0.0f) return false;
                    return ray_color.add(shader.shade(value, g, position * spacing), alpha);
                });
                detail::tally(counters, marched);
            }
            return ray_color.over(settings.background);
        });
    if (stats != nullptr) *stats = total;
    return image;
}

}  // namespace pp5
