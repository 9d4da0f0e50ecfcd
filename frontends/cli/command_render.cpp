// `pp5sim render [SCENARIO]`: render every frame of a scenario on a configured machine and write the
// images, stats.json and config.json.
//
// With the levoy kernel the whole frame runs on the simulated machine (kernels/levoy/levoy_renderer.h):
// the renderers' PPs classify and shade, the GPs cast rays pass after pass of adaptive refinement with
// voxels fetched over the ring. Every frame is also rendered by the floating-point reference renderer,
// and stats.json says how far the two images are apart.
// With the reference kernel the host renderer alone makes the images and simulated time is zero.

#include "frontends/cli/commands.h"
#include "frontends/cli/output_dir.h"
#include "frontends/cli/progress.h"
#include "frontends/run_config.h"
#include "frontends/image_io.h"
#include "frontends/scenario.h"
#include "kernels/levoy/levoy_renderer.h"
#include "kernels/reference/composite.h"
#include "kernels/reference/reference_renderer.h"
#include "sim/core/config.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <optional>
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
    std::string trace;                  // Chrome trace-event JSON file; empty: none
    std::string trace_window = "0:inf"; // simulated milliseconds
    std::size_t trace_limit = 500000;   // events
};

// "START:END" in simulated milliseconds ("inf" for no end).
std::pair<Tick, Tick> parse_trace_window(const std::string& text) {
    const auto fail = [&](const std::string& why) { throw InputError("--trace-window", "--trace-window", why); };
    const auto colon = text.find(':');
    if (colon == std::string::npos) fail("expected START:END in simulated milliseconds, e.g. 0:50");
    const auto parse_ms = [&](const std::string& part) -> Tick {
        if (part == "inf") return kMaxTick;
        std::size_t used = 0;
        double ms = 0.0;
        try {
            ms = std::stod(part, &used);
        } catch (const std::exception&) {
            fail("'" + part + "' is not a number of milliseconds");
        }
        if (used != part.size() || !std::isfinite(ms) || ms < 0.0 || ms > 1e9) fail("'" + part + "' is not a number of milliseconds from 0");
        return static_cast<Tick>(ms * 1e9);
    };
    const Tick start = parse_ms(text.substr(0, colon));
    const Tick end = parse_ms(text.substr(colon + 1));
    if (end <= start) fail("the window ends before it starts");
    return {start, end};
}

using Seconds = std::chrono::duration<double>;

nlohmann::json pass_record(const PpProgramPass& pass) {
    if (!pass.ran) return {{"ran", false}};
    return {{"ran", true},
            {"simulated_seconds", static_cast<double>(pass.end_ps - pass.start_ps) / static_cast<double>(kTicksPerSecond)},
            {"instructions", pass.instructions},
            {"local_memory_bits_used", pass.local_memory_bits_used},
            {"slot_cycles", pass.slot_cost.compute_cycles()},
            {"slot_alu_cycles", pass.slot_cost.alu_cycles},
            {"slot_controller_cycles", pass.slot_cost.controller_cycles},
            {"slot_transfer_cycles", pass.slot_cost.transfer_cycles()},
            {"slots", pass.slots},
            {"cycles", {{"total", pass.busiest.total},
                        {"computation", pass.busiest.alu},
                        {"controller", pass.busiest.controller},
                        {"backing_store", pass.busiest.backing_store_stall}}}};
}

// One frame's record in stats.json: what changed, what the reference did, what the machine did.
double seconds(Tick t) { return ticks_to_seconds(t); }

// The machine's side of a frame: where the time went and what the GPs did.
nlohmann::json machine_record(const LevoyFrameReport& f, const std::vector<std::string>& pass_images) {
    const RayCastReport& rc = f.ray_cast;
    const double cast_seconds = seconds(rc.end - rc.start);
    const double gps = rc.gp_busy + rc.gp_wait > 0 ? 1.0 : 0.0;
    nlohmann::json passes = nlohmann::json::array();
    for (std::size_t i = 0; i < f.passes.size(); ++i) {
        const RefinementPassReport& p = f.passes[i];
        passes.push_back({{"pass", i},
                          {"image", pass_images.at(i)},
                          {"complete_seconds", seconds(p.end_ps)},
                          {"rays", p.rays},
                          {"samples", p.samples},
                          {"pixels_cast_so_far", p.pixels_cast}});
    }
    const std::uint64_t lookups = rc.cache_hits + rc.cache_misses;
    return {{"simulated_seconds", seconds(f.duration_ps())},
            {"crude_seconds", f.passes.empty() ? 0.0 : seconds(f.passes.front().end_ps)},
            {"refined_seconds", seconds(f.duration_ps())},
            {"phases",
             {{"pixel_processors_seconds", seconds(f.pixel_processors.duration_ps())},
              {"pyramid_seconds", seconds(f.pyramid_ps)},
              {"ray_casting_seconds", cast_seconds}}},
            {"ray_casting_breakdown",
             {{"gp_computing_seconds", seconds(rc.gp_busy)},
              {"gp_waiting_seconds", seconds(rc.gp_wait)},
              {"ring_busy_seconds", seconds(rc.ring_busy)},
              {"renderers_answering_seconds", seconds(rc.renderer_busy)},
              {"note", "each summed over the GPs, channels or renderers; ray_casting_seconds is wall time"},
              {"gp_busy_fraction", gps > 0 ? static_cast<double>(rc.gp_busy) / static_cast<double>(rc.gp_busy + rc.gp_wait) : 0.0}}},
            {"pyramid_rebuilt", f.pyramid_rebuilt},
            {"pyramid_cells_occupied", f.pyramid_cells_occupied},
            {"caches_invalidated", f.caches_invalidated},
            {"depth_buffer_used", f.depth_buffer_used},
            {"rays", rc.rays},
            {"samples", rc.samples},
            {"samples_skipped", rc.samples_skipped},
            {"pyramid_steps", rc.pyramid_steps},
            {"rays_terminated", rc.rays_terminated},
            {"pixels_filled", rc.pixels_filled},
            {"cache", {{"hits", rc.cache_hits}, {"misses", rc.cache_misses},
                       {"hit_rate", lookups == 0 ? 0.0 : static_cast<double>(rc.cache_hits) / static_cast<double>(lookups)}}},
            {"voxel_requests", rc.requests},
            {"context_switches", rc.context_switches},
            {"events", rc.events},
            {"passes", passes}};
}

nlohmann::json frame_record(std::size_t index, const FrameSpec& frame, const std::string& image_name,
                            const RenderStats& stats, const std::optional<LevoyFrameReport>& machine_work,
                            const std::vector<std::string>& pass_images,
                            const std::optional<ImageDifference>& fidelity, double host_seconds, bool polygons) {
    nlohmann::json record = {
        {"index", index},
        {"label", frame.label},
        {"image", image_name},
        {"changed", {{"camera", frame.camera_changed}, {"lighting", frame.lighting_changed},
                     {"classification", frame.classification_changed}, {"region", frame.region_changed}}},
        {"simulated_seconds", machine_work ? seconds(machine_work->duration_ps()) : 0.0},
        {"reference",
         {{"rays", stats.composite.rays},
          {"samples", stats.composite.samples},
          {"samples_skipped", stats.composite.samples_skipped},
          {"rays_terminated", stats.composite.rays_terminated}}},
        {"host_seconds", host_seconds}};
    if (machine_work) {
        record["renderers"] = {{"classification", pass_record(machine_work->pixel_processors.classification)},
                               {"region_of_interest", pass_record(machine_work->region)},
                               {"shading", pass_record(machine_work->pixel_processors.shading)}};
        const GeometryReport& g = machine_work->geometry;
        record["geometry"] = {{"ran", g.ran},
                              {"polygons", g.polygons},
                              {"slot_runs", g.slots},
                              {"simulated_seconds", seconds(g.end_ps - g.start_ps)},
                              {"polygons_per_second", g.polygons_per_second()}};
        record["machine"] = machine_record(*machine_work, pass_images);
    }
    if (fidelity) {
        record["fidelity"] = {{"against", polygons ? "reference renderer, which has no polygons: the difference includes them"
                                                   : "reference renderer"},
                              {"psnr_db", std::isfinite(fidelity->psnr_db) ? nlohmann::json(fidelity->psnr_db) : nlohmann::json("inf")},
                              {"rms_error", fidelity->rms_error},
                              {"max_error", fidelity->max_error}};
    }
    return record;
}

std::string describe_frame(const nlohmann::json& f) {
    std::string line = fmt::format("  frame {} ({}): host reference {} samples ({} skipped as empty)", f["index"].get<std::size_t>(),
                                   f["label"].get<std::string>(), f["reference"]["samples"].dump(),
                                   f["reference"]["samples_skipped"].dump());
    if (f.contains("renderers")) {
        for (const char* pass : {"classification", "region_of_interest", "shading"}) {
            const auto& p = f["renderers"][pass];
            if (!p["ran"].get<bool>()) continue;
            line += fmt::format("; PP {} {:.2f} ms ({} cycles a slot)", pass, p["simulated_seconds"].get<double>() * 1e3,
                                p["slot_cycles"].dump());
        }
        if (f["geometry"]["ran"].get<bool>())
            line += fmt::format("; {} polygons scan-converted in {:.2f} ms ({:.0f} a second)", f["geometry"]["polygons"].dump(),
                                f["geometry"]["simulated_seconds"].get<double>() * 1e3,
                                f["geometry"]["polygons_per_second"].get<double>());
        const auto& m = f["machine"];
        line += fmt::format("\n    GPs: {} rays in {} passes, {} samples ({} skipped), cache hit rate {:.1f}%; crude {:.1f} ms, "
                            "refined {:.1f} ms simulated",
                            m["rays"].dump(), m["passes"].size(), m["samples"].dump(), m["samples_skipped"].dump(),
                            100.0 * m["cache"]["hit_rate"].get<double>(), m["crude_seconds"].get<double>() * 1e3,
                            m["refined_seconds"].get<double>() * 1e3);
    }
    if (f.contains("fidelity")) {
        const auto& psnr = f["fidelity"]["psnr_db"];
        line += psnr.is_number() ? fmt::format("; PSNR {:.1f} dB against the reference", psnr.get<double>())
                                 : std::string("; identical to the reference");
    }
    return line;
}

int run_render(const RenderOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    // Read and check every input before any work or output.
    const Scenario scenario = load_scenario(resolve_scenario_file(o.scenario));
    const MachineConfig config = load_run_config(o.machine, o.overrides);
    if (o.threads < 0) throw InputError("--threads", "--threads", "must be 0 (all cores) or more");
    if (o.format != "png" && o.format != "exr") throw InputError("--format", "--format", "must be png or exr");
    if (config.machine_kind() == MachineKind::Uniprocessor) {
        throw InputError(resolve_machine_file(o.machine).string(), "machine.kind",
                         "a uniprocessor machine is timed from recorded work by `pp5sim fit` and `pp5sim reproduce` (targets "
                         "naming it); `render` simulates Pixel-planes 5 machines only");
    }
    const bool on_machine = scenario.kernel == ScenarioKernel::Levoy;
    if (on_machine && scenario.image.resampling != ResamplingOrder::ShadeThenInterpolate) {
        throw InputError(scenario.file.string(), "image.resampling",
                         "the levoy kernel shades at the voxels (shade-then-interpolate); use kernel = \"reference\" to "
                         "interpolate first");
    }
    const ImageFormat format = o.format == "png" ? ImageFormat::Png : ImageFormat::Exr;
    std::optional<TraceRecorder> trace;
    if (!o.trace.empty()) {
        const auto [from, to] = parse_trace_window(o.trace_window);
        trace.emplace(from, to, o.trace_limit);
    }
    Machine machine(config);
    if (trace) machine.attach_trace(&*trace);
    const Volume volume = load_dataset(scenario);

    const std::size_t threads = o.threads > 0 ? static_cast<std::size_t>(o.threads)
                                              : std::max(1u, std::thread::hardware_concurrency());
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);

    // The machine's kernel places the volume in the PPs first: a volume that does not fit stops here.
    std::optional<LevoyRenderer> workstation;
    if (on_machine) {
        workstation.emplace(machine, volume, LevoySettings::from(config), levoy_image_settings(scenario.image));
        workstation->set_polygons(scenario.polygons);
    }

    StagedOutput output(o.out.empty() ? std::filesystem::path("out") / scenario.name : std::filesystem::path(o.out));
    ReferenceRenderer reference(volume);
    const RenderSettings settings = reference_render_settings(scenario.image);
    nlohmann::json frames = nlohmann::json::array();
    nlohmann::json simulated = nlohmann::json::array();
    Progress progress("render " + scenario.name, scenario.frames.size());
    for (std::size_t i = 0; i < scenario.frames.size(); ++i) {
        const FrameSpec& frame = scenario.frames[i];
        const auto frame_start = std::chrono::steady_clock::now();
        const Camera camera = frame_camera(frame, volume);
        if (frame.classification_changed) reference.set_classification(frame.classification, frame.colors);
        if (frame.lighting_changed) reference.set_lighting(frame.lighting);
        RenderStats stats;
        Image image = reference.render(camera, settings, &stats);
        const Image reference_image = on_machine ? image : Image();

        std::optional<LevoyFrameReport> machine_work;
        std::optional<ImageDifference> fidelity;
        std::vector<std::string> pass_images;
        if (workstation) {
            machine_work = workstation->render(levoy_frame_inputs(frame, volume));
            for (std::size_t p = 0; p < machine_work->passes.size(); ++p) {
                pass_images.push_back(fmt::format("frame_{:04}_pass_{}.{}", i, p, o.format));
                output.add_image(pass_images.back(), std::move(machine_work->passes[p].image), format);
            }
            // The last pass's picture is the frame; pass images were moved out, so read it back.
            image = std::move(machine_work->final_image);
            fidelity = compare_images(image, reference_image);
        }
        const std::string image_name = fmt::format("frame_{:04}.{}", i, o.format);
        output.add_image(image_name, std::move(image), format);
        const double host = Seconds(std::chrono::steady_clock::now() - frame_start).count();
        frames.push_back(frame_record(i, frame, image_name, stats, machine_work, pass_images, fidelity, host, !scenario.polygons.empty()));
        simulated.push_back(frames.back()["simulated_seconds"]);
        progress.update(i + 1);
    }
    const double host_seconds = Seconds(std::chrono::steady_clock::now() - started).count();

    nlohmann::json summary = {{"scenario", scenario.name},
                              {"kernel", on_machine ? "levoy" : "reference"},
                              {"machine", config.machine_name()},
                              {"frames", scenario.frames.size()},
                              {"image_size", {scenario.image.width, scenario.image.height}},
                              {"simulated_seconds", simulated},
                              {"timing_model", on_machine ? "event-driven: PP passes from their programs' operations, the pyramid's "
                                                            "distribution and building, and the GPs' ray casting with voxel "
                                                            "requests over the ring; uncalibrated default costs"
                                                          : "none: the host reference renderer; simulated time is 0"},
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
    if (workstation) {
        const VoxelPlacement& p = workstation->pixel_processors().placement();
        const VoxelQuantization& q = workstation->pixel_processors().quantization();
        stats["placement"] = {{"policy", to_string(p.policy())},
                              {"record_bits", p.record_bits()},
                              {"slots_needed", p.slots_needed()},
                              {"slots_available", p.slots_available()},
                              {"backing_store_bits_used", p.backing_store_bits_used()},
                              {"value_scale", q.value_scale},
                              {"value_offset", q.value_offset},
                              {"gradient_scale", q.gradient_scale}};
    }
    output.add_text("stats.json", stats.dump(2) + "\n");
    output.add_text("config.json", config.to_json().dump(2) + "\n");
    auto written = output.commit();
    if (trace) {
        const std::filesystem::path trace_path(o.trace);
        StagedOutput trace_output(trace_path.has_parent_path() ? trace_path.parent_path() : std::filesystem::path("."));
        trace_output.add_text(trace_path.filename().string(), trace->to_text());
        for (auto& p : trace_output.commit()) written.push_back(std::move(p));
        fmt::print("  trace: {} events{} in {}\n", trace->events(),
                   trace->dropped() > 0 ? fmt::format(" ({} more past --trace-limit)", trace->dropped()) : std::string(), o.trace);
    }

    fmt::print("pp5sim render: scenario {} on machine {} ({} kernel)\n", scenario.name, config.machine_name(),
               on_machine ? "levoy" : "reference");
    fmt::print("  {}\n", machine.summary());
    fmt::print("  dataset {}: {}x{}x{} {}, values {} to {}\n", volume.name(), volume.dims().x, volume.dims().y,
               volume.dims().z, to_string(volume.source_type()), volume.min_value(), volume.max_value());
    for (const auto& f : frames) fmt::print("{}\n", describe_frame(f));
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
    cmd->add_option("--trace", o->trace,
                   "Write a Chrome trace-event JSON file of the run (GPs, renderers, ring messages; open it in Perfetto)");
    cmd->add_option("--trace-window", o->trace_window, "Simulated milliseconds to trace, START:END (END may be inf)")
        ->capture_default_str();
    cmd->add_option("--trace-limit", o->trace_limit, "Most events the trace keeps")->capture_default_str();
    cmd->callback([o, &run] { run = [o] { return run_render(*o); }; });
}

}  // namespace pp5::cli
