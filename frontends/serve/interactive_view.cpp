#include "frontends/serve/interactive_view.h"

#include "calibration/timing_model.h"
#include "frontends/compare_kernels.h"
#include "frontends/lecture_pictures.h"
#include "frontends/serve/view_request.h"
#include "kernels/registry/registry.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace pp5 {

namespace {

using view_request::kRequest;
using view_request::only_keys;
using view_request::read_camera_change;
using view_request::read_light_change;
using view_request::read_region_change;
using view_request::refuse;

// A recorder with no trace-event window, keeping the slices of the frame being timed: a 512x512 frame
// of the MR head makes about (measured in the tests) a few hundred thousand.
std::unique_ptr<TraceRecorder> timeline_recorder() {
    auto recorder = std::make_unique<TraceRecorder>(0, 0, 0);
    recorder->keep_slices(2'000'000);
    return recorder;
}

nlohmann::json to_json(glm::vec3 v) { return {v.x, v.y, v.z}; }

// The parameters the page puts in front of a class, with their values and whether changing one only
// re-times the frame.
nlohmann::json machine_controls(const MachineConfig& config) {
    nlohmann::json controls = nlohmann::json::array();
    const nlohmann::json parameters = config.to_json()["parameters"];
    const auto add = [&](const std::string& key, const char* group) {
        if (!parameters.contains(key)) return;
        const nlohmann::json& p = parameters[key];
        controls.push_back({{"key", key},
                            {"value", p["value"]},
                            {"unit", p["unit"]},
                            {"timing_only", is_timing_parameter(key)},
                            {"group", group},
                            {"origin", p.value("origin", "")}});
    };
    for (const char* key : {"gp.count", "renderer.count", "ring.clock_mhz", "ring.channels", "gp.cache_bits"})
        add(key, "machine");
    // The calibration in force: the fitted scales on the documented costs (1 where nothing was fitted).
    for (const auto& [key, entry] : parameters.items())
        if (key.starts_with("calibration.") && key.ends_with("_scale")) add(key, "calibration");
    return controls;
}

// Voxels the region moves for one pixel of drag along the screen's right and up: what lets the page
// move the region under the pointer.
nlohmann::json drag_basis(const FrameSpec& frame, const Volume& volume, const ImageSpec& image) {
    const Camera camera = frame_camera(frame, volume);
    const ViewBasis basis = view_basis(camera);
    const float world_per_pixel = camera.projection == Projection::Parallel
                                      ? camera.view_height / static_cast<float>(image.height)
                                      : 2.0f * std::tan(glm::radians(camera.fov_y_degrees) * 0.5f) *
                                            glm::length(camera.target - camera.eye) / static_cast<float>(image.height);
    const glm::vec3 spacing = volume.spacing();
    return {{"right", to_json(basis.right * world_per_pixel / spacing)},
            {"up", to_json(basis.up * world_per_pixel / spacing)}};
}

}  // namespace

InteractiveView::InteractiveView(Scenario scenario, MachineConfig config)
    : scenario_(std::move(scenario)), config_(std::move(config)), trace_(timeline_recorder()), timing_(config_) {
    current_ = scenario_.frames.front();
    session_ = start_session(scenario_, config_);
    render(current_);
}

void InteractiveView::apply(const nlohmann::json& change) {
    only_keys(change, "", {"camera", "light", "region", "kernel", "machine"});
    if (change.contains("machine")) {
        if (change.size() > 1)
            refuse("machine", "a change to the machine comes alone, so that what it did to the frame is its own");
        return change_machine(change["machine"]);
    }
    FrameSpec next = current_;
    next.label = "change";
    next.camera_changed = next.lighting_changed = next.classification_changed = next.region_changed = false;

    if (change.contains("camera")) {
        read_camera_change(change["camera"], next.camera);
        next.camera_changed = !(next.camera.azimuth_degrees == current_.camera.azimuth_degrees &&
                                next.camera.elevation_degrees == current_.camera.elevation_degrees &&
                                next.camera.zoom == current_.camera.zoom);
    }
    if (change.contains("light")) {
        read_light_change(change["light"], next.lighting);
        next.lighting_changed = !(next.lighting == current_.lighting);
    }
    if (change.contains("region")) {
        next.region = read_region_change(change["region"], current_.region, session_->volume().dims());
        next.region_changed = next.region != current_.region;
    }

    // Another kernel, or other stationary lights (which set how the kernel lays out what it keeps),
    // start the run again on the view as it stands.
    std::string kernel = scenario_.kernel;
    if (change.contains("kernel")) {
        if (!change["kernel"].is_string()) refuse("kernel", "expected a kernel's name");
        kernel = change["kernel"].get<std::string>();
    }
    const bool other_lights = next.lighting.stationary_lights != current_.lighting.stationary_lights;
    if (kernel != scenario_.kernel || other_lights) {
        Scenario other = scenario_;
        other.kernel = kernel;
        other.frames = {next};
        try {
            auto session = start_session(other, timing_);
            scenario_ = std::move(other);
            session_ = std::move(session);
            config_ = timing_;
            recent_.clear();
            phase_names_.clear();
        } catch (const InputError& e) {
            if (kernel != scenario_.kernel)
                refuse("kernel", fmt::format("{} cannot render this view: {}", kernel, e.what()));
            refuse("light.stationary", fmt::format("{} cannot render these lights: {}", kernel, e.what()));
        }
        next.camera_changed = next.lighting_changed = next.classification_changed = true;
        next.region_changed = next.region.has_value();
    }
    if (!session_->kernel().runs_on_machine() || session_->frames_rendered() == 0 || next.camera_changed ||
        next.lighting_changed || next.classification_changed || next.region_changed)
        render(next);
}

std::unique_ptr<RenderSession> InteractiveView::start_session(const Scenario& scenario, const MachineConfig& config) {
    auto session = std::make_unique<RenderSession>(scenario, config, trace_.get());
    session->defer_reference_comparison();  // the picture first; its PSNR when the page asks
    return session;
}

void InteractiveView::render(FrameSpec frame) {
    SessionFrame rendered = session_->render(frame);
    current_ = frame;
    current_.camera_changed = current_.lighting_changed = current_.classification_changed = current_.region_changed =
        false;

    passes_.clear();
    for (FrameImage& image : rendered.images)
        if (image.kind == FrameImage::Kind::Pass) passes_.push_back(std::move(image.image));
    const Image* picture = rendered.find(FrameImage::Kind::Frame);
    frame_png_ = encode_png(*picture);
    picture_ = *picture;
    fidelity_ = nullptr;  // a new picture: its distance from the reference is not known yet
    ++version_;

    machine_change_ = nullptr;
    last_record_ = rendered.record;
    describe(rendered.index, rendered.record, *rendered.recorded, rendered.timing);
    recent_.push_back(std::move(rendered.recorded));
    if (recent_.size() > 2) recent_.erase(recent_.begin());
}

void InteractiveView::describe(std::size_t index, const nlohmann::json& record, const KernelFrame& recorded,
                               const FrameTiming& timing) {
    const Kernel& kernel = session_->kernel();
    nlohmann::json metrics = nlohmann::json::array();
    for (const KernelMetric& m : kernel.metrics()) {
        try {
            metrics.push_back({{"name", m.name},
                               {"unit", m.unit},
                               {"description", m.description},
                               {"value", kernel.metric(m.name, recorded, timing)}});
        } catch (const std::domain_error&) {
            // This frame cannot give it (a polygon rate without polygons): not shown.
        }
    }
    // Every phase this session has run, so that what a change did not need shows as kept.
    for (const PhaseTiming& p : timing.phases)
        if (std::find(phase_names_.begin(), phase_names_.end(), p.name) == phase_names_.end())
            phase_names_.push_back(p.name);
    nlohmann::json phases = nlohmann::json::array();
    for (const std::string& name : phase_names_) {
        const PhaseTiming* p = timing.phase(name);
        const Tick duration = p != nullptr ? p->duration_ps() : 0;
        phases.push_back({{"name", name}, {"seconds", ticks_to_seconds(duration)}, {"ran", duration > 0}});
    }
    // When each pass reached the frame buffer: the GP phase that ends a group of tiles per pass.
    nlohmann::json ready = nlohmann::json::array();
    for (const PhaseTiming& p : timing.phases)
        if (passes_.size() > 1 && p.group_end_ps.size() == passes_.size())
            for (const Tick end : p.group_end_ps) ready.push_back(ticks_to_seconds(end - timing.start_ps));
    last_timing_ = timing;
    tile_map_ = gp_tile_map(recorded.work, timing, session_->timing_machine().gps().size(), picture_);
    const double seconds = ticks_to_seconds(timing.duration_ps());
    last_ = {{"index", index},
             {"changed", record["changed"]},
             {"simulated_seconds", seconds},
             {"frames_per_second", seconds > 0 ? nlohmann::json(1.0 / seconds) : nlohmann::json(nullptr)},
             {"metrics", metrics},
             {"phases", phases},
             {"passes", passes_.size()},
             {"passes_ready_seconds", ready},
             {"tile_map", tile_map_.has_value()},
             {"utilisation",
              {{"gps", timing.activity.gps}, {"renderers", timing.activity.renderers}, {"ring", timing.activity.ring}}},
             {"psnr_db", fidelity_.is_null() ? nlohmann::json(nullptr) : fidelity_["psnr_db"]},
             {"psnr_pending", fidelity_.is_null() && session_->kernel().runs_on_machine()},
             {"host_seconds", record["host_seconds"]},
             {"record", record}};
}

void InteractiveView::change_machine(const nlohmann::json& change) {
    if (!change.is_object() || change.empty())
        refuse("machine", "expected an object of parameter = value, e.g. {\"gp.count\": 64}");
    MachineConfig wanted = timing_;
    for (const auto& [key, value] : change.items()) {
        const std::string field = "machine." + key;
        ParamValue parsed;
        if (value.is_boolean()) parsed = value.get<bool>();
        else if (value.is_number_integer()) parsed = value.get<std::int64_t>();
        else if (value.is_number()) parsed = value.get<double>();
        else if (value.is_string()) parsed = value.get<std::string>();
        else refuse(field, "expected a number, true or false, or text");
        // A whole number sent as 32.0 (as a slider may) counts as one.
        if (const ParamSpec* spec = wanted.find_spec(key);
            spec != nullptr && spec->type == ParamType::Integer && value.is_number_float()) {
            const double v = value.get<double>();
            if (v == std::floor(v) && std::abs(v) < 9e15) parsed = static_cast<std::int64_t>(v);
        }
        try {
            wanted.set(key, parsed, kRequest);
        } catch (const InputError& e) {
            refuse(field, e.reason());
        }
    }
    // What differs from the machine now, compared as config.json writes the values.
    const nlohmann::json now = timing_.to_json()["parameters"], next = wanted.to_json()["parameters"];
    std::vector<std::string> changed;
    bool timing_only = true;
    for (const auto& [key, value] : change.items()) {
        if (next[key]["value"] == now[key]["value"]) continue;
        changed.push_back(key);
        timing_only = timing_only && is_timing_parameter(key);
    }
    if (changed.empty()) return;  // the machine it already is
    const auto started = std::chrono::steady_clock::now();
    if (timing_only && session_->kernel().runs_on_machine() && !recent_.empty()) {
        // What the kernels computed stands: the last frames are timed again on the changed machine.
        std::vector<const FrameWork*> replay;
        for (const auto& frame : recent_) replay.push_back(&frame->work);
        const FrameTiming retimed = session_->retime_on(wanted, replay);
        timing_ = std::move(wanted);
        describe(last_["index"].get<std::size_t>(), last_record_, *recent_.back(), retimed);
        last_["changed"] = {{"machine", changed}};
        ++version_;
        machine_change_ = {
            {"kind", "re-timed"},
            {"keys", changed},
            {"frames_replayed", replay.size()},
            {"host_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()}};
        return;
    }
    // It changes what is computed (or there is nothing recorded to re-time): the frame is rendered again.
    try {
        auto session = start_session(scenario_, wanted);
        session_ = std::move(session);
    } catch (const InputError& e) {
        refuse("machine", fmt::format("this machine cannot render the view: {}", e.what()));
    }
    config_ = wanted;
    timing_ = std::move(wanted);
    recent_.clear();
    phase_names_.clear();
    FrameSpec again = current_;
    again.label = "change";
    render(again);
    last_["changed"] = {{"machine", changed}};
    machine_change_ = {
        {"kind", "rendered again"},
        {"keys", changed},
        {"host_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()}};
}

nlohmann::json InteractiveView::state() const {
    nlohmann::json kernels = nlohmann::json::array();
    for (const Kernel* k : pp5::kernels()) {
        Scenario other = scenario_;
        other.kernel = k->name();
        bool usable = true;
        try {
            check_scenario(*k, other);
        } catch (const InputError&) {
            usable = false;
        }
        if (usable) kernels.push_back({{"name", k->name()}, {"description", k->description()}});
    }
    const Volume& volume = session_->volume();
    nlohmann::json region = nullptr;
    if (current_.region) {
        const RegionOfInterest& r = *current_.region;
        region = {{"shape", r.shape == RegionOfInterest::Shape::Box ? "box" : "ellipsoid"},
                  {"center", to_json(r.center)},
                  {"half_size", to_json(r.half_size)},
                  {"scale_inside", r.scale_inside},
                  {"scale_outside", r.scale_outside},
                  {"transition", r.transition},
                  {"cap", r.cap}};
    }
    nlohmann::json stationary = nlohmann::json::array();
    for (const StationaryLight& light : current_.lighting.stationary_lights)
        stationary.push_back({{"direction", to_json(light.direction)}, {"intensity", light.intensity}});
    return {{"version", version_},
            {"scenario", scenario_.name},
            {"description", scenario_.description},
            {"kernel", scenario_.kernel},
            {"kernels", kernels},
            {"machine", config_.machine_name()},
            {"machine_summary", session_->timing_machine().summary()},
            {"machine_parameters", machine_controls(timing_)},
            {"machine_change", machine_change_},
            {"image", {{"width", scenario_.image.width}, {"height", scenario_.image.height}}},
            {"volume", {{"name", volume.name()}, {"dims", {volume.dims().x, volume.dims().y, volume.dims().z}}}},
            {"camera",
             {{"azimuth", current_.camera.azimuth_degrees},
              {"elevation", current_.camera.elevation_degrees},
              {"zoom", current_.camera.zoom}}},
            {"light",
             {{"direction", to_json(current_.lighting.light_direction)},
              {"headlight", current_.lighting.light_follows_camera},
              {"stationary", stationary}}},
            {"region", region},
            {"region_drag", drag_basis(current_, volume, scenario_.image)},
            {"frame", last_}};
}

nlohmann::json InteractiveView::timeline(int bins) const {
    const FrameTimeline t = frame_timeline(*trace_, last_timing_, session_->timing_machine().trace_track_names(), bins);
    nlohmann::json phases = nlohmann::json::array();
    for (const PhaseTiming& p : last_timing_.phases)
        phases.push_back({{"name", p.name},
                          {"start", ticks_to_seconds(p.start_ps - t.start_ps)},
                          {"end", ticks_to_seconds(p.end_ps - t.start_ps)}});
    nlohmann::json lanes = nlohmann::json::array();
    for (const TimelineLane& lane : t.lanes) {
        // Two decimals are all a pixel's shade can show, and keep the document small; a bin with any
        // busy time at all stays above zero, so that it still shows.
        std::vector<double> busy;
        for (const float b : lane.busy) busy.push_back(b > 0.0f ? std::max(0.01, std::round(b * 100.0) / 100.0) : 0.0);
        lanes.push_back({{"group", lane.group}, {"name", lane.name}, {"busy", busy}, {"what", lane.what}});
    }
    return {{"version", version_},
            {"seconds", ticks_to_seconds(t.end_ps - t.start_ps)},
            {"bins", t.bins},
            {"phases", phases},
            {"passes_ready_seconds", last_["passes_ready_seconds"]},
            {"activities", t.activities},
            {"lanes", lanes},
            {"slices_dropped", t.slices_dropped}};
}

std::optional<std::string> InteractiveView::tile_map_png() const {
    if (!tile_map_) return std::nullopt;
    return encode_png(*tile_map_);
}

nlohmann::json InteractiveView::compare_kernels() {
    Scenario view = scenario_;
    FrameSpec frame = current_;
    frame.label = "view";
    view.frames = {frame};
    const KernelComparison comparison = pp5::compare_kernels(view, timing_);
    comparison_pictures_.clear();
    for (const KernelComparisonRow& row : comparison.rows)
        if (row.rendered()) comparison_pictures_.emplace_back(row.kernel, row.picture);
    nlohmann::json report = to_json(comparison);
    report["version"] = version_;  // the view it compared
    return report;
}

std::optional<std::string> InteractiveView::comparison_png(const std::string& kernel) const {
    for (const auto& [name, picture] : comparison_pictures_)
        if (name == kernel) return encode_png(picture);
    return std::nullopt;
}

nlohmann::json InteractiveView::reference_fidelity() {
    if (fidelity_.is_null() && session_->kernel().runs_on_machine()) {
        fidelity_ = session_->compare_with_reference(current_, picture_);
        if (!fidelity_.is_null()) {
            last_["psnr_db"] = fidelity_["psnr_db"];
            last_["psnr_pending"] = false;
        }
    }
    return {{"version", version_}, {"fidelity", fidelity_}};
}

}  // namespace pp5
