#include "frontends/run_config.h"

#include "kernels/levoy/levoy_costs.h"
#include "kernels/levoy/pp_shading.h"
#include "sim/machine/machine.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace pp5 {

std::vector<const ParamGroup*> run_param_groups() {
    std::vector<const ParamGroup*> groups = Machine::param_groups();
    groups.push_back(&LevoySettings::params());
    groups.push_back(&levoy_cost_params());
    return groups;
}

MachineConfig load_run_config(const std::string& machine, const std::vector<std::string>& overrides) {
    MachineConfig config(run_param_groups());
    config.load_file(resolve_machine_file(machine));
    for (const auto& assignment : overrides) config.apply_override(assignment);
    return config;
}

LevoyImageSettings levoy_image_settings(const ImageSpec& spec) {
    LevoyImageSettings image;
    image.width = spec.width;
    image.height = spec.height;
    image.sample_step = spec.sample_step;
    image.termination_opacity = spec.termination_opacity;
    image.background = spec.background;
    return image;
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

Camera frame_camera(const FrameSpec& frame, const Volume& volume) {
    const glm::vec3 extent = glm::vec3(volume.dims() - 1) * volume.spacing();
    const float radius = std::max(0.5f * glm::length(extent), 1e-3f);
    return frame.camera.camera_for(0.5f * extent, radius);
}

LevoyFrameInputs levoy_frame_inputs(const FrameSpec& frame, const Volume& volume) {
    return LevoyFrameInputs{frame_camera(frame, volume), frame.classification, frame.colors, frame.lighting,
                            frame.classification_changed, frame.lighting_changed, frame.region};
}

}  // namespace pp5
