#include "frontends/render_scenario.h"

#include "kernels/reference/reference_renderer.h"
#include "kernels/registry/registry.h"
#include "kernels/scenario/scenario_inputs.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"
#include "sim/timing/frame_engine.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <optional>

namespace pp5 {

namespace {

using Seconds = std::chrono::duration<double>;

// One frame's record in stats.json: what changed, what the kernel and the machine did, how far the
// picture is from the reference renderer's.
nlohmann::json frame_record(std::size_t index, const FrameSpec& frame, const std::string& image_name, const FrameTiming& timing,
                            nlohmann::json kernel_stats, const std::optional<ImageDifference>& fidelity, double host_seconds,
                            bool polygons) {
    nlohmann::json record = {
        {"index", index},
        {"label", frame.label},
        {"image", image_name},
        {"changed", {{"camera", frame.camera_changed}, {"lighting", frame.lighting_changed},
                     {"classification", frame.classification_changed}, {"region", frame.region_changed}}},
        {"simulated_seconds", ticks_to_seconds(timing.duration_ps())},
        {"host_seconds", host_seconds}};
    for (auto& [key, value] : kernel_stats.items()) record[key] = std::move(value);
    if (fidelity) {
        record["fidelity"] = {{"against", polygons ? "reference renderer, which has no polygons: the difference includes them"
                                                   : "reference renderer"},
                              {"psnr_db", std::isfinite(fidelity->psnr_db) ? nlohmann::json(fidelity->psnr_db) : nlohmann::json("inf")},
                              {"rms_error", fidelity->rms_error},
                              {"max_error", fidelity->max_error}};
    }
    return record;
}

std::string describe_frame(const nlohmann::json& f, const KernelRun& run) {
    std::string line = fmt::format("  frame {} ({}): host reference {} samples ({} skipped as empty)", f["index"].get<std::size_t>(),
                                   f["label"].get<std::string>(), f["reference"]["samples"].dump(),
                                   f["reference"]["samples_skipped"].dump());
    line += run.describe(f);
    // Levoy's figures are rates: the frame's beside its milliseconds.
    if (f.contains("simulated_seconds") && f["simulated_seconds"].is_number() && f["simulated_seconds"].get<double>() > 0)
        line += fmt::format(" ({:.1f} frames a second)", 1.0 / f["simulated_seconds"].get<double>());
    if (f.contains("fidelity")) {
        const auto& psnr = f["fidelity"]["psnr_db"];
        line += psnr.is_number() ? fmt::format("; PSNR {:.1f} dB against the reference", psnr.get<double>())
                                 : std::string("; identical to the reference");
    }
    return line;
}

}  // namespace

ScenarioRender render_scenario(const Scenario& scenario, const MachineConfig& config, StagedOutput& output,
                               const ScenarioRenderOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const Kernel& kernel = kernel_for(scenario);
    kernel.check(scenario);
    const bool on_machine = kernel.runs_on_machine();
    const ImageFormat format = options.format;
    const char* extension = format == ImageFormat::Png ? "png" : "exr";
    Machine machine(config);
    if (options.trace != nullptr) machine.attach_trace(options.trace);
    if (on_machine) check_picture_fits(machine, scenario.image.width, scenario.image.height);
    const Volume volume = load_dataset(scenario);

    // The kernel sets the scenario up on the machine first: a volume that does not fit stops here.
    const std::unique_ptr<KernelRun> run = kernel.start(machine, config, scenario, volume);

    // The oracle every machine kernel's pictures are compared with.
    std::optional<ReferenceRenderer> reference;
    if (on_machine) reference.emplace(volume);
    const RenderSettings settings = reference_render_settings(scenario.image);
    nlohmann::json frames = nlohmann::json::array();
    nlohmann::json simulated = nlohmann::json::array();
    for (std::size_t i = 0; i < scenario.frames.size(); ++i) {
        const FrameSpec& frame = scenario.frames[i];
        const auto frame_start = std::chrono::steady_clock::now();
        std::optional<Image> reference_image;
        RenderStats reference_counts;
        if (reference) {
            if (frame.classification_changed) reference->set_classification(frame.classification, frame.colors);
            if (frame.lighting_changed) reference->set_lighting(frame.lighting);
            reference_image = reference->render(frame_camera(frame, volume), settings, &reference_counts);
        }

        std::unique_ptr<KernelFrame> recorded = run->record_frame(frame);
        const FrameTiming timing = on_machine ? time_frame(machine, recorded->work) : FrameTiming{};
        std::vector<std::string> pass_images;
        // Each stage against the reference, with its difference image, for kernels whose stages are
        // alternatives (the low-resolution volume alone, then with its points).
        nlohmann::json pass_fidelity = nlohmann::json::array();
        if (reference_image && recorded->compare_passes_with_reference) {
            for (std::size_t p = 0; p < recorded->pass_images.size(); ++p) {
                const Image& pass = recorded->pass_images[p];
                const ImageDifference d = compare_images(pass, *reference_image);
                const std::string name = fmt::format("frame_{:04}_pass_{}_difference.{}", i, p, extension);
                output.add_image(name, inverted_difference(pass, *reference_image), format);
                pass_fidelity.push_back({{"pass", p},
                                         {"psnr_db", std::isfinite(d.psnr_db) ? nlohmann::json(d.psnr_db) : nlohmann::json("inf")},
                                         {"rms_error", d.rms_error},
                                         {"difference_image", name}});
            }
        }
        Image image = std::move(recorded->pass_images.back());
        if (on_machine) {
            for (std::size_t p = 0; p < recorded->pass_images.size(); ++p) {
                pass_images.push_back(fmt::format("frame_{:04}_pass_{}.{}", i, p, extension));
                output.add_image(pass_images.back(), p + 1 == recorded->pass_images.size() ? Image(image) : std::move(recorded->pass_images[p]),
                                 format);
            }
        }
        nlohmann::json kernel_stats = run->frame_stats(*recorded, timing, pass_images);
        if (reference) kernel_stats["reference"] = reference_stats(reference_counts);
        if (!pass_fidelity.empty()) kernel_stats["fidelity_by_pass"] = std::move(pass_fidelity);
        std::optional<ImageDifference> fidelity;
        if (reference_image) fidelity = compare_images(image, *reference_image);
        const std::string image_name = fmt::format("frame_{:04}.{}", i, extension);
        output.add_image(image_name, std::move(image), format);
        const double host = Seconds(std::chrono::steady_clock::now() - frame_start).count();
        frames.push_back(frame_record(i, frame, image_name, timing, std::move(kernel_stats), fidelity, host, !scenario.polygons.empty()));
        simulated.push_back(frames.back()["simulated_seconds"]);
        if (options.progress) options.progress(i + 1, scenario.frames.size());
    }
    const double host_seconds = Seconds(std::chrono::steady_clock::now() - started).count();

    nlohmann::json summary = {{"scenario", scenario.name},
                              {"kernel", kernel.name()},
                              {"machine", config.machine_name()},
                              {"frames", scenario.frames.size()},
                              {"image_size", {scenario.image.width, scenario.image.height}},
                              {"simulated_seconds", simulated},
                              {"timing_model", kernel.timing_summary()},
                              {"host_seconds", host_seconds}};
    nlohmann::json stats = {
        {"summary", summary},
        {"dataset",
         {{"name", volume.name()},
          {"dims", {volume.dims().x, volume.dims().y, volume.dims().z}},
          {"spacing", {volume.spacing().x, volume.spacing().y, volume.spacing().z}},
          {"type", std::string(to_string(volume.source_type()))},
          {"value_range", {volume.min_value(), volume.max_value()}}}},
        {"frames", frames},
        {"simulation", {{"events_run", machine.events().events_run()}, {"simulated_ticks_ps", machine.events().now()}}},
        {"components", machine.statistics()}};
    if (nlohmann::json placement = run->run_stats(); !placement.is_null()) stats["placement"] = std::move(placement);
    output.add_text("stats.json", stats.dump(2) + "\n");
    output.add_text("config.json", config.to_json().dump(2) + "\n");

    ScenarioRender result;
    result.lines.push_back(fmt::format("pp5sim render: scenario {} on machine {} ({} kernel)", scenario.name, config.machine_name(), kernel.name()));
    result.lines.push_back(fmt::format("  {}", machine.summary()));
    result.lines.push_back(fmt::format("  dataset {}: {}x{}x{} {}, values {} to {}", volume.name(), volume.dims().x, volume.dims().y,
                                       volume.dims().z, to_string(volume.source_type()), volume.min_value(), volume.max_value()));
    for (const auto& f : frames) result.lines.push_back(describe_frame(f, *run));
    result.stats = std::move(stats);
    return result;
}

}  // namespace pp5
