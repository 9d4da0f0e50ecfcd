#include "scene/scenario/scenario_inputs.h"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace pp5 {

Camera frame_camera(const FrameSpec& frame, const Volume& volume) {
    const glm::vec3 extent = glm::vec3(volume.dims() - 1) * volume.spacing();
    const float radius = std::max(0.5f * glm::length(extent), 1e-3f);
    return frame.camera.camera_for(0.5f * extent, radius);
}

RenderSettings reference_render_settings(const ImageSpec& image) {
    RenderSettings s;
    s.width = image.width;
    s.height = image.height;
    s.background = image.background;
    s.sample_step = image.sample_step;
    s.termination_opacity = image.termination_opacity;
    s.resampling = image.resampling;
    return s;
}

nlohmann::json reference_stats(const RenderStats& stats) {
    return {{"rays", stats.composite.rays},
            {"samples", stats.composite.samples},
            {"samples_skipped", stats.composite.samples_skipped},
            {"rays_terminated", stats.composite.rays_terminated}};
}

}  // namespace pp5
