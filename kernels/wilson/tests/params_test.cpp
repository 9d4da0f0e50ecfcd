// Every wilson.* parameter changes what a frame computes, and every gp_cost.wilson.* cost changes its
// simulated time on the machine it applies to (Pixel-planes 5, or a lone processor for the work the
// PPs and renderers do there). The 200x200 picture spans four regions, so quads cross region edges.

#include "calibration/timing_model.h"
#include "kernels/registry/run_config.h"
#include "kernels/wilson/wilson_costs.h"
#include "kernels/wilson/wilson_settings.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

Scenario scene(const std::string& name, const std::string& projection) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("pp5sim_wilson_params_" + std::to_string(::getpid()) + "_" + name + ".toml");
    std::ofstream(path)
        << "[scenario]\nkernel = \"wilson\"\n[dataset]\nphantom = \"head\"\nsize = 40\n[classification]\n"
           "kind = \"isovalue-contours\"\ncontours = [{ value = 60.0, opacity = 0.5, thickness = 1.5 }, "
           "{ value = 160.0, opacity = 0.9, thickness = 1.5 }]\n[shading]\nambient = 0.3\ndiffuse = 0.7\n"
           "specular = 0.0\nlight_direction = [0.3, 0.5, -1]\n[camera]\nprojection = \""
        << projection << "\"\nview_from = [0.3, -1.0, 0.4]\nup = [0.0, 0.0, 1.0]\n[image]\nwidth = 200\nheight = 200\n";
    Scenario s = load_scenario(path);
    std::filesystem::remove(path);
    return s;
}

// What a frame computed and how long it took, as one comparable string.
std::string outcome(const Scenario& s, const std::vector<std::string>& overrides) {
    const MachineConfig config = load_run_config("pxpl5", overrides);
    const RecordedScenario recorded(s, config, 1);
    const FrameTiming timing = recorded.time_on(config).front();
    std::string digest = std::to_string(ticks_to_seconds(timing.duration_ps()));
    for (const glm::vec4& p : recorded.frames().front().refined_image.pixels)
        digest += std::to_string(static_cast<int>(p.r * 4096));
    return digest;
}

TEST(WilsonParameters, EachChangesTheFrame) {
    const Scenario s = scene("kernel", "parallel");
    const std::string base = outcome(s, {});
    const std::vector<std::string> changes = {
        "wilson.downsample_factor=3",     "wilson.downsample=box",      "wilson.downsample=min",
        "wilson.overestimate_limit=2",    "wilson.error_grid_factor=2", "wilson.error_threshold=0.1",
        "wilson.error_sign=positive",     "wilson.max_points=50",       "wilson.point_overlap=2",
        "wilson.point_opacity_scale=0.5", "wilson.point_path=renderer", "wilson.opacity_correction=none",
        "wilson.brick_voxels=4",          "wilson.accumulator_bits=10"};
    for (const std::string& change : changes) EXPECT_NE(outcome(s, {change}), base) << change;
    // And the list is complete.
    EXPECT_EQ(changes.size() - 1, WilsonSettings::params().specs().size());
}

TEST(WilsonParameters, EachCostChangesTheTimeWhereItApplies) {
    for (const char* projection : {"parallel", "perspective"}) {
        const Scenario s = scene(std::string("costs_") + projection, projection);
        const MachineConfig recording = load_run_config("pxpl5", {"wilson.point_path=gp_sheets"});
        const RecordedScenario sheets(s, recording, 1);
        const MachineConfig renderer_path = load_run_config("pxpl5", {"wilson.point_path=renderer"});
        const RecordedScenario primitives(s, renderer_path, 1);
        for (const ParamSpec& spec : wilson_cost_params().specs()) {
            const std::string key = "gp_cost.wilson." + spec.name;
            const bool lone = spec.name.starts_with("voxel_") ||
                              (spec.name.ends_with("_pixel_flops") && spec.name != "sheet_pixel_flops");
            if ((spec.name == "quad_perspective_flops") != (std::string(projection) == "perspective") &&
                spec.name.starts_with("quad_"))
                continue;  // each quad cost applies under its own camera
            const std::string machine = lone ? "sun4-280" : "pxpl5";
            // The renderer path has no sheet pixels, the sheet path no point coefficients; try both.
            bool changed = false;
            for (const RecordedScenario* r : {&sheets, &primitives}) {
                const MachineConfig base = load_run_config(
                    machine, {std::string("wilson.point_path=") + (r == &sheets ? "gp_sheets" : "renderer")});
                MachineConfig doubled = base;
                doubled.set(key, base.real(key) * 2 + 1, "test");
                changed |= r->time_on(base).front().duration_ps() != r->time_on(doubled).front().duration_ps();
            }
            EXPECT_TRUE(changed) << key << " (" << projection << ", " << machine << ")";
        }
    }
}

}  // namespace
}  // namespace pp5
