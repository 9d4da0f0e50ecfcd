#include "frontends/render_session.h"

#include "calibration/timing_model.h"
#include "kernels/registry/registry.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/calibration.h"
#include "sim/core/host_memory.h"
#include "sim/timing/frame_engine.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>

namespace pp5 {

namespace {

using Seconds = std::chrono::duration<double>;

nlohmann::json psnr_json(double psnr_db) {
    return std::isfinite(psnr_db) ? nlohmann::json(psnr_db) : nlohmann::json("inf");
}

// How far a picture is from the reference renderer's, as a frame record says it.
nlohmann::json fidelity_json(const ImageDifference& d, const std::string& against) {
    return {{"against", against},
            {"psnr_db", psnr_json(d.psnr_db)},
            {"rms_error", d.rms_error},
            {"max_error", d.max_error}};
}

// One frame's record in stats.json: what changed, what the kernel and the machine did, how far the
// picture is from the reference renderer's.
nlohmann::json frame_record(std::size_t index, const FrameSpec& frame, const std::string& image_name,
                            const FrameTiming& timing, nlohmann::json kernel_stats,
                            const std::optional<ImageDifference>& fidelity, double host_seconds,
                            const std::string& against) {
    nlohmann::json record = {{"index", index},
                             {"label", frame.label},
                             {"image", image_name},
                             {"changed",
                              {{"camera", frame.camera_changed},
                               {"lighting", frame.lighting_changed},
                               {"classification", frame.classification_changed},
                               {"region", frame.region_changed}}},
                             {"simulated_seconds", ticks_to_seconds(timing.duration_ps())},
                             {"host_seconds", host_seconds}};
    for (auto& [key, value] : kernel_stats.items()) record[key] = std::move(value);
    if (fidelity) record["fidelity"] = fidelity_json(*fidelity, against);
    return record;
}

std::string describe_frame(const nlohmann::json& f, const KernelRun& run) {
    std::string line = fmt::format("  frame {} ({})", f["index"].get<std::size_t>(), f["label"].get<std::string>());
    if (const auto reference = f.find("reference"); reference != f.end()) {
        line += fmt::format(": host reference {} samples ({} skipped as empty)", (*reference)["samples"].dump(),
                            (*reference)["samples_skipped"].dump());
    }
    line += run.describe(f);
    // Levoy's figures are rates: the frame's beside its milliseconds.
    if (f.contains("simulated_seconds") && f["simulated_seconds"].is_number() &&
        f["simulated_seconds"].get<double>() > 0)
        line += fmt::format(" ({:.1f} frames a second)", 1.0 / f["simulated_seconds"].get<double>());
    if (const auto band = f.find("uncertainty"); band != f.end())
        line += fmt::format(" [95% over the guesses' ranges: {:.4g}-{:.4g} ms]",
                            1e3 * (*band)["simulated_seconds_low"].get<double>(),
                            1e3 * (*band)["simulated_seconds_high"].get<double>());
    if (f.contains("fidelity")) {
        const auto& psnr = f["fidelity"]["psnr_db"];
        line += psnr.is_number() ? fmt::format("; PSNR {:.1f} dB against the reference", psnr.get<double>())
                                 : std::string("; identical to the reference");
    }
    return line;
}

const Kernel& checked_kernel(const Scenario& scenario) {
    const Kernel& kernel = kernel_for(scenario);
    check_scenario(kernel, scenario);
    return kernel;
}

}  // namespace

const Image* SessionFrame::find(FrameImage::Kind kind, std::size_t pass) const {
    for (auto it = images.rbegin(); it != images.rend(); ++it)
        if (it->kind == kind && (kind == FrameImage::Kind::Frame || it->pass == pass)) return &it->image;
    return nullptr;
}

double picture_bytes_per_frame(const Kernel& kernel, const Scenario& scenario, const MachineConfig& config,
                               bool compare_with_reference) {
    constexpr double kRgbaBytes = 16.0;
    constexpr double kComparisonBuffersBytes = 2 * 12.0;
    const double pixels = static_cast<double>(scenario.image.width) * static_cast<double>(scenario.image.height);
    const auto pictures = static_cast<double>(kernel.most_pictures_per_frame(config));
    double per_pixel = kRgbaBytes * pictures;  // the passes; off the machine the last is the frame
    if (kernel.runs_on_machine()) {
        // The frame's own copy beside its passes, then the reference and the difference images.
        per_pixel += kRgbaBytes;
        if (compare_with_reference) {
            const double differences = kernel.compares_each_picture() ? pictures : 0.0;
            per_pixel += kRgbaBytes * (1 + differences) + kComparisonBuffersBytes;
        }
    }
    return pixels * per_pixel;
}

Volume RenderSession::load_checked_volume(TraceRecorder* trace) {
    if (trace != nullptr) machine_.attach_trace(trace);
    // What the picture needs of the frame buffer is known before the volume is read.
    if (kernel_.runs_on_machine()) check_picture_fits(machine_, scenario_.image.width, scenario_.image.height);
    check_fits_host_memory(
        scenario_.file.string(), "image.width",
        picture_bytes_per_frame(kernel_, scenario_, config_, compare_with_reference_),
        fmt::format("holding a {}x{} frame's pictures", scenario_.image.width, scenario_.image.height));
    // When the scenario gives the volume's size, one the machine cannot hold is refused before reading it.
    if (const auto dims = scenario_.dataset.known_dims(); dims && kernel_.runs_on_machine())
        naming_parameter_origins(config_, [&] { kernel_.check_volume_fits(machine_, config_, scenario_, *dims); });
    const ScopedActivity activity("loading the volume of " + scenario_.file.string());
    return load_dataset(scenario_);
}

RenderSession::RenderSession(const Scenario& scenario, const MachineConfig& config, TraceRecorder* trace,
                             std::string extension, bool compare_with_reference)
    : scenario_(scenario),
      config_(config),
      kernel_(checked_kernel(scenario_)),
      extension_(std::move(extension)),
      compare_with_reference_(compare_with_reference),
      machine_(config_),
      trace_(trace),
      volume_(load_checked_volume(trace)) {
    // The kernel sets the scenario up on the machine first: a volume that does not fit stops here.
    const ScopedActivity activity(
        fmt::format("setting {} up on the machine for the {} kernel", scenario_.name, kernel_.name()));
    run_ = naming_parameter_origins(config_, [&] { return kernel_.start(machine_, config_, scenario_, volume_); });
    // The oracle every machine kernel's pictures are compared with.
    if (kernel_.runs_on_machine() && compare_with_reference_) {
        reference_.emplace(volume_);
        reference_->set_polygons(scenario_.polygons);
    }
}

FrameTiming RenderSession::retime_on(const MachineConfig& timing, const std::vector<const FrameWork*>& replay) {
    check_only_timing_differs(config_, timing, "the frame must be rendered again");
    timing_machine_.reset();  // it refers to the configuration replaced next
    timing_config_ = timing;
    timing_machine_ = std::make_unique<Machine>(*timing_config_);
    if (trace_ != nullptr) timing_machine_->attach_trace(trace_);
    FrameTiming last;
    if (!kernel_.runs_on_machine()) return last;
    for (const FrameWork* work : replay) {
        if (trace_ != nullptr) trace_->forget_slices();
        last = time_frame(*timing_machine_, *work);
    }
    return last;
}

// What the oracle's picture holds of the frame, for stats.json: the difference includes whatever it leaves out.
std::string RenderSession::reference_includes(const FrameSpec& frame) const {
    std::string against = "reference renderer (floating point): the volume, classified and shaded";
    if (!frame.lighting.stationary_lights.empty()) against += ", with its stationary lights";
    std::vector<std::string> missing;
    const bool voxel_order = ReferenceRenderer::renders_region(reference_render_settings(scenario_.image));
    if (frame.region) {
        if (!voxel_order) missing.push_back("the region of interest");
        else
            against += frame.region->cap ? ", the region of interest's opacity scaling and capping"
                                         : ", the region of interest's opacity scaling";
    }
    if (!scenario_.polygons.empty()) {
        if (!voxel_order) missing.push_back("the polygons");
        else
            against +=
                fmt::format(", its polygons scan-converted with {} subvoxel samples", PolygonMattes::kOracleSamples);
    }
    for (std::size_t i = 0; i < missing.size(); ++i)
        against += (i == 0 ? "; without " : i + 1 == missing.size() ? " and " : ", ") + missing[i];
    if (!missing.empty()) against += ", so the difference includes them";
    return against;
}

SessionFrame RenderSession::render(FrameSpec frame) {
    if (frames_rendered_ == 0) frame.camera_changed = frame.lighting_changed = frame.classification_changed = true;
    const std::size_t index = frames_rendered_;
    const bool with_reference = reference_ && !defer_reference_;
    const ScopedActivity activity(fmt::format("rendering frame {} ({}) of {}{}", index, frame.label, scenario_.name,
                                              with_reference ? " and its reference picture" : ""));
    const auto frame_start = std::chrono::steady_clock::now();
    reference_classification_stale_ = reference_classification_stale_ || frame.classification_changed;
    reference_lighting_stale_ = reference_lighting_stale_ || frame.lighting_changed;
    std::optional<Image> reference_image;
    RenderStats reference_counts;
    if (with_reference) reference_image = render_reference(frame, &reference_counts);

    SessionFrame out;
    out.index = index;
    std::unique_ptr<KernelFrame> recorded =
        naming_parameter_origins(config_, [&] { return run_->record_frame(frame); });
    const bool on_machine = kernel_.runs_on_machine();
    Machine& timed = timing_machine_ ? *timing_machine_ : machine_;
    if (trace_ != nullptr) trace_->forget_slices();
    out.timing = on_machine ? time_frame(timed, recorded->work) : FrameTiming{};

    // Each stage against the reference, with its difference image, for kernels whose stages are
    // alternatives (the low-resolution volume alone, then with its points).
    nlohmann::json pass_fidelity = nlohmann::json::array();
    if (reference_image && recorded->compare_passes_with_reference) {
        for (std::size_t p = 0; p < recorded->pass_images.size(); ++p) {
            const Image& pass = recorded->pass_images[p];
            const ImageDifference d = compare_images(pass, *reference_image);
            const std::string name = fmt::format("frame_{:04}_pass_{}_difference.{}", index, p, extension_);
            out.images.push_back({FrameImage::Kind::Difference, p, name, inverted_difference(pass, *reference_image)});
            pass_fidelity.push_back({{"pass", p},
                                     {"psnr_db", psnr_json(d.psnr_db)},
                                     {"rms_error", d.rms_error},
                                     {"difference_image", name}});
        }
    }
    Image image = std::move(recorded->pass_images.back());
    std::vector<std::string> pass_names;
    if (on_machine) {
        for (std::size_t p = 0; p < recorded->pass_images.size(); ++p) {
            pass_names.push_back(fmt::format("frame_{:04}_pass_{}.{}", index, p, extension_));
            out.images.push_back(
                {FrameImage::Kind::Pass, p, pass_names.back(),
                 p + 1 == recorded->pass_images.size() ? Image(image) : std::move(recorded->pass_images[p])});
        }
    }
    nlohmann::json kernel_stats = run_->frame_stats(*recorded, out.timing, pass_names);
    if (with_reference) kernel_stats["reference"] = reference_stats(reference_counts);
    if (!pass_fidelity.empty()) kernel_stats["fidelity_by_pass"] = std::move(pass_fidelity);
    if (on_machine)
        kernel_stats["utilisation"] = {{"gps", out.timing.activity.gps},
                                       {"renderers", out.timing.activity.renderers},
                                       {"ring", out.timing.activity.ring}};
    std::optional<ImageDifference> fidelity;
    if (reference_image) fidelity = compare_images(image, *reference_image);
    const std::string image_name = fmt::format("frame_{:04}.{}", index, extension_);
    out.images.push_back({FrameImage::Kind::Frame, 0, image_name, std::move(image)});
    const double host = Seconds(std::chrono::steady_clock::now() - frame_start).count();
    out.record = frame_record(index, frame, image_name, out.timing, std::move(kernel_stats), fidelity, host,
                              reference_includes(frame));
    out.recorded = std::move(recorded);
    ++frames_rendered_;
    return out;
}

Image RenderSession::render_reference(const FrameSpec& frame, RenderStats* counts) {
    if (reference_classification_stale_) reference_->set_classification(frame.classification, frame.colors);
    if (reference_lighting_stale_) reference_->set_lighting(frame.lighting);
    reference_classification_stale_ = reference_lighting_stale_ = false;
    reference_->set_region(frame.region);
    return reference_->render(frame_camera(frame, volume_), reference_render_settings(scenario_.image), counts);
}

nlohmann::json RenderSession::compare_with_reference(const FrameSpec& frame, const Image& picture) {
    if (!reference_) return nullptr;
    const ScopedActivity activity("rendering the reference picture of " + scenario_.name);
    return fidelity_json(compare_images(picture, render_reference(frame, nullptr)), reference_includes(frame));
}

nlohmann::json RenderSession::stats(const nlohmann::json& frames, double host_seconds) const {
    nlohmann::json simulated = nlohmann::json::array();
    for (const auto& f : frames) simulated.push_back(f["simulated_seconds"]);
    const nlohmann::json summary = {
        {"scenario", scenario_.name},
        {"kernel", kernel_.name()},
        {"machine", config_.machine_name()},
        {"frames", frames.size()},
        {"image_size", {scenario_.image.width, scenario_.image.height}},
        {"simulated_seconds", simulated},
        {"timing_model", kernel_.runs_on_machine() ? kernel_.timing_summary() + "; " + describe_calibration(config_)
                                                   : kernel_.timing_summary()},
        {"host_seconds", host_seconds}};
    nlohmann::json stats = {
        {"summary", summary},
        {"dataset",
         {{"name", volume_.name()},
          {"dims", {volume_.dims().x, volume_.dims().y, volume_.dims().z}},
          {"spacing", {volume_.spacing().x, volume_.spacing().y, volume_.spacing().z}},
          {"type", std::string(to_string(volume_.source_type()))},
          {"value_range", {volume_.min_value(), volume_.max_value()}}}},
        {"frames", frames},
        {"simulation",
         {{"events_run", machine_.events().events_run()}, {"simulated_ticks_ps", machine_.events().now()}}},
        {"components", machine_.statistics()}};
    if (nlohmann::json placement = run_->run_stats(); !placement.is_null()) stats["placement"] = std::move(placement);
    return stats;
}

std::vector<std::string> RenderSession::summary_lines(const nlohmann::json& frames) const {
    std::vector<std::string> lines;
    lines.push_back(fmt::format("pp5sim render: scenario {} on machine {} ({} kernel)", scenario_.name,
                                config_.machine_name(), kernel_.name()));
    lines.push_back(fmt::format("  {}", machine_.summary()));
    lines.push_back(fmt::format("  dataset {}: {}x{}x{} {}, values {} to {}", volume_.name(), volume_.dims().x,
                                volume_.dims().y, volume_.dims().z, to_string(volume_.source_type()),
                                volume_.min_value(), volume_.max_value()));
    for (const auto& f : frames) lines.push_back(describe_frame(f, *run_));
    return lines;
}

}  // namespace pp5
