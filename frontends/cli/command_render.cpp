// `pp5sim render [SCENARIO]`: render every frame of a scenario on a configured machine and write the
// images, stats.json and config.json.
//
// The scenario's kernel (kernels/registry) computes each frame and records its work; the timing
// engine times it on the machine. With the levoy kernel the whole frame runs on the simulated machine:
// the renderers' PPs classify and shade, the GPs cast rays pass after pass of adaptive refinement with
// voxels fetched over the ring. Every frame is also rendered by the floating-point reference renderer,
// and stats.json says how far the two images are apart.
// With the reference kernel the host renderer alone makes the images and simulated time is zero.

#include "frontends/cli/commands.h"
#include "frontends/cli/output_dir.h"
#include "frontends/cli/progress.h"
#include "kernels/registry/run_config.h"
#include "frontends/image_io.h"
#include "kernels/scenario/scenario.h"
#include "kernels/registry/registry.h"
#include "kernels/scenario/scenario_inputs.h"
#include "sim/timing/frame_engine.h"
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
    const Kernel& kernel = kernel_for(scenario);
    kernel.check(scenario);
    const bool on_machine = kernel.runs_on_machine();
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

    // The kernel sets the scenario up on the machine first: a volume that does not fit stops here.
    const std::unique_ptr<KernelRun> run = kernel.start(machine, config, scenario, volume);

    StagedOutput output(o.out.empty() ? std::filesystem::path("out") / scenario.name : std::filesystem::path(o.out));
    // The oracle every machine kernel's pictures are compared with.
    std::optional<ReferenceRenderer> reference;
    if (on_machine) reference.emplace(volume);
    const RenderSettings settings = reference_render_settings(scenario.image);
    nlohmann::json frames = nlohmann::json::array();
    nlohmann::json simulated = nlohmann::json::array();
    Progress progress("render " + scenario.name, scenario.frames.size());
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
        Image image = std::move(recorded->pass_images.back());
        if (on_machine) {
            for (std::size_t p = 0; p < recorded->pass_images.size(); ++p) {
                pass_images.push_back(fmt::format("frame_{:04}_pass_{}.{}", i, p, o.format));
                output.add_image(pass_images.back(), p + 1 == recorded->pass_images.size() ? Image(image) : std::move(recorded->pass_images[p]),
                                 format);
            }
        }
        nlohmann::json kernel_stats = run->frame_stats(*recorded, timing, pass_images);
        if (reference) kernel_stats["reference"] = reference_stats(reference_counts);
        std::optional<ImageDifference> fidelity;
        if (reference_image) fidelity = compare_images(image, *reference_image);
        const std::string image_name = fmt::format("frame_{:04}.{}", i, o.format);
        output.add_image(image_name, std::move(image), format);
        const double host = Seconds(std::chrono::steady_clock::now() - frame_start).count();
        frames.push_back(frame_record(i, frame, image_name, timing, std::move(kernel_stats), fidelity, host, !scenario.polygons.empty()));
        simulated.push_back(frames.back()["simulated_seconds"]);
        progress.update(i + 1);
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
    auto written = output.commit();
    if (trace) {
        const std::filesystem::path trace_path(o.trace);
        StagedOutput trace_output(trace_path.has_parent_path() ? trace_path.parent_path() : std::filesystem::path("."));
        trace_output.add_text(trace_path.filename().string(), trace->to_text());
        for (auto& p : trace_output.commit()) written.push_back(std::move(p));
        fmt::print("  trace: {} events{} in {}\n", trace->events(),
                   trace->dropped() > 0 ? fmt::format(" ({} more past --trace-limit)", trace->dropped()) : std::string(), o.trace);
    }

    fmt::print("pp5sim render: scenario {} on machine {} ({} kernel)\n", scenario.name, config.machine_name(), kernel.name());
    fmt::print("  {}\n", machine.summary());
    fmt::print("  dataset {}: {}x{}x{} {}, values {} to {}\n", volume.name(), volume.dims().x, volume.dims().y,
               volume.dims().z, to_string(volume.source_type()), volume.min_value(), volume.max_value());
    for (const auto& f : frames) fmt::print("{}\n", describe_frame(f, *run));
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
