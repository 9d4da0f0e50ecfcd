// `pp5sim render [SCENARIO]`: render every frame of a scenario on a configured machine and write the
// images, stats.json and config.json.
//
// Until the machine's timing arrives, each frame is rendered by the host reference renderer and its
// simulated time is zero; the machine is still assembled from the configuration, so its parameters
// are validated and its components report their statistics.

#include "frontends/cli/commands.h"
#include "frontends/cli/output_dir.h"
#include "frontends/cli/progress.h"
#include "frontends/scenario.h"
#include "kernels/reference/reference_renderer.h"
#include "sim/core/config.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <chrono>
#include <thread>

namespace pp5::cli {
namespace {

struct RenderOptions {
    std::string scenario = kDefaultScenario;
    std::string machine = "pxpl5";
    std::vector<std::string> overrides;
    std::string out;
    int threads = 0;  // 0 = every core
    std::string format = "png";
};

using Seconds = std::chrono::duration<double>;

RenderSettings render_settings(const ImageSpec& image) {
    RenderSettings s;
    s.width = image.width;
    s.height = image.height;
    s.background = image.background;
    s.sample_step = image.sample_step;
    s.termination_opacity = image.termination_opacity;
    s.resampling = image.resampling;
    return s;
}

nlohmann::json frame_record(std::size_t index, const FrameSpec& frame, const std::string& image_name,
                            const RenderStats& stats, double host_seconds) {
    return {{"index", index},
            {"label", frame.label},
            {"image", image_name},
            {"changed", {{"camera", frame.camera_changed}, {"lighting", frame.lighting_changed},
                         {"classification", frame.classification_changed}}},
            {"simulated_seconds", 0.0},
            {"reference",
             {{"rays", stats.composite.rays},
              {"samples", stats.composite.samples},
              {"samples_skipped", stats.composite.samples_skipped},
              {"rays_terminated", stats.composite.rays_terminated}}},
            {"host_seconds", host_seconds}};
}

int run_render(const RenderOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    // Read and check every input before any work or output.
    const Scenario scenario = load_scenario(resolve_scenario_file(o.scenario));
    MachineConfig config = Machine::default_config();
    config.load_file(resolve_machine_file(o.machine));
    for (const auto& assignment : o.overrides) config.apply_override(assignment);
    if (o.threads < 0) throw InputError("--threads", "--threads", "must be 0 (all cores) or more");
    if (o.format != "png" && o.format != "exr") throw InputError("--format", "--format", "must be png or exr");
    const ImageFormat format = o.format == "png" ? ImageFormat::Png : ImageFormat::Exr;
    Machine machine(config);
    const Volume volume = load_dataset(scenario);

    const std::size_t threads = o.threads > 0 ? static_cast<std::size_t>(o.threads)
                                              : std::max(1u, std::thread::hardware_concurrency());
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);

    const glm::vec3 extent = glm::vec3(volume.dims() - 1) * volume.spacing();
    const glm::vec3 center = 0.5f * extent;
    const float radius = std::max(0.5f * glm::length(extent), 1e-3f);

    StagedOutput output(o.out.empty() ? std::filesystem::path("out") / scenario.name : std::filesystem::path(o.out));
    ReferenceRenderer renderer(volume);
    const RenderSettings settings = render_settings(scenario.image);
    nlohmann::json frames = nlohmann::json::array();
    nlohmann::json simulated = nlohmann::json::array();
    Progress progress("render " + scenario.name, scenario.frames.size());
    for (std::size_t i = 0; i < scenario.frames.size(); ++i) {
        const FrameSpec& frame = scenario.frames[i];
        const auto frame_start = std::chrono::steady_clock::now();
        if (frame.classification_changed) renderer.set_classification(frame.classification, frame.colors);
        if (frame.lighting_changed) renderer.set_lighting(frame.lighting);
        RenderStats stats;
        Image image = renderer.render(frame.camera.camera_for(center, radius), settings, &stats);
        const std::string image_name = fmt::format("frame_{:04}.{}", i, o.format);
        output.add_image(image_name, std::move(image), format);
        const double host = Seconds(std::chrono::steady_clock::now() - frame_start).count();
        frames.push_back(frame_record(i, frame, image_name, stats, host));
        simulated.push_back(0.0);
        progress.update(i + 1);
    }
    const double host_seconds = Seconds(std::chrono::steady_clock::now() - started).count();

    nlohmann::json stats = {
        {"summary",
         {{"scenario", scenario.name},
          {"machine", config.machine_name()},
          {"frames", scenario.frames.size()},
          {"image_size", {scenario.image.width, scenario.image.height}},
          {"simulated_seconds", simulated},
          {"timing_model", "none yet: frames are rendered by the host reference renderer; simulated time is 0"},
          {"host_seconds", host_seconds}}},
        {"dataset",
         {{"name", volume.name()},
          {"dims", {volume.dims().x, volume.dims().y, volume.dims().z}},
          {"spacing", {volume.spacing().x, volume.spacing().y, volume.spacing().z}},
          {"type", std::string(to_string(volume.source_type()))},
          {"value_range", {volume.min_value(), volume.max_value()}}}},
        {"frames", frames},
        {"simulation", {{"events_run", machine.events().events_run()}, {"simulated_ticks_ps", machine.events().now()}}},
        {"components", machine.statistics()}};
    output.add_text("stats.json", stats.dump(2) + "\n");
    output.add_text("config.json", config.to_json().dump(2) + "\n");
    const auto written = output.commit();

    fmt::print("pp5sim render: scenario {} on machine {}\n", scenario.name, config.machine_name());
    fmt::print("  {}\n", machine.summary());
    fmt::print("  dataset {}: {}x{}x{} {}, values {} to {}\n", volume.name(), volume.dims().x, volume.dims().y,
               volume.dims().z, to_string(volume.source_type()), volume.min_value(), volume.max_value());
    for (const auto& f : frames)
        fmt::print("  frame {} ({}): {} rays, {} samples ({} skipped as empty), simulated {} s\n",
                   f["index"].get<std::size_t>(), f["label"].get<std::string>(), f["reference"]["rays"].dump(),
                   f["reference"]["samples"].dump(), f["reference"]["samples_skipped"].dump(),
                   f["simulated_seconds"].dump());
    fmt::print("  host time {:.2f} s with {} thread{}\n", host_seconds, threads, threads == 1 ? "" : "s");
    fmt::print("wrote {} files to {}\n", written.size(), output.directory().string());
    return 0;
}

}  // namespace

void add_render_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scenario's frames on a configured machine");
    cmd->add_option("scenario", o->scenario,
                   "Scenario file (TOML) or the name of a shipped one (traces/scenarios/); default: the MR head")
        ->capture_default_str();
    cmd->add_option("--machine", o->machine, "Machine file or preset name")->capture_default_str();
    cmd->add_option("--set", o->overrides, "Override a machine parameter, key=value (repeatable; see `pp5sim params`)");
    cmd->add_option("--out", o->out, "Output directory (default out/<scenario name>)");
    cmd->add_option("--threads", o->threads, "Host threads; 0 uses every core. Results do not depend on it")
        ->capture_default_str();
    cmd->add_option("--format", o->format, "Image format: png or exr")->capture_default_str();
    cmd->callback([o, &run] { run = [o] { return run_render(*o); }; });
}

}  // namespace pp5::cli
