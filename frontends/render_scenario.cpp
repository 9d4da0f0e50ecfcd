#include "frontends/render_scenario.h"

#include "frontends/render_session.h"

#include "calibration/timing_model.h"
#include "calibration/uncertainty.h"

#include "frontends/lecture_pictures.h"
#include "frontends/staged_plot.h"

#include <fmt/core.h>

#include <chrono>
#include <optional>

namespace pp5 {

namespace {

void add_lecture_pictures(const SessionFrame& frame, const Machine& machine, const TraceRecorder& trace,
                          StagedOutput& output, std::vector<std::string>& warnings) {
    const std::size_t gp_count = machine.gps().size();
    std::vector<Image> passes;
    for (const FrameImage& image : frame.images)
        if (image.kind == FrameImage::Kind::Pass) passes.push_back(image.image);
    if (passes.size() > 1) {
        output.add_image(fmt::format("frame_{:04}_passes_strip.png", frame.index), passes_strip(passes),
                         ImageFormat::Png);
        output.add_text(fmt::format("frame_{:04}_passes.gif", frame.index), encode_gif(passes, 1.5f));
    }
    if (const Image* picture = frame.find(FrameImage::Kind::Frame))
        if (auto map = gp_tile_map(frame.recorded->work, frame.timing, gp_count, *picture))
            output.add_image(fmt::format("frame_{:04}_gp_tiles.png", frame.index), std::move(*map), ImageFormat::Png);
    if (frame.timing.duration_ps() > 0) {
        const std::map<std::string, std::size_t> counts = {
            {"GPs", gp_count},
            {"renderers", machine.renderers().size()},
            {"ring", static_cast<std::size_t>(machine.ring().channel_count())}};
        const std::string name = fmt::format("frame_{:04}_utilisation", frame.index);
        if (auto warning = stage_plot(
                output, utilisation_over_time(trace, frame.timing.start_ps, frame.timing.end_ps, counts), name))
            warnings.push_back(std::move(*warning));
    }
}

// Each frame's band, in its record, and what was moved, in stats.json's `uncertainty`.
nlohmann::json add_frame_bands(const MachineConfig& config, const Kernel& kernel,
                               const std::vector<std::unique_ptr<KernelFrame>>& recorded, nlohmann::json& frames) {
    std::vector<const FrameWork*> work;
    for (const auto& frame : recorded) work.push_back(&frame->work);
    const FigureEvaluator frame_seconds = [&](const MachineConfig& machine) {
        std::vector<double> seconds;
        for (const FrameTiming& t : time_recorded_work(machine, work))
            seconds.push_back(ticks_to_seconds(t.duration_ps()));
        return seconds;
    };
    const auto started = std::chrono::steady_clock::now();
    const UncertaintyTable table = measure_uncertainty(config, uncertain_parameters(config, {&kernel}), frame_seconds);
    for (std::size_t f = 0; f < frames.size(); ++f) {
        if (!frames[f].contains("simulated_seconds"))
            continue;  // a frame with no simulated time (the reference kernel's)
        const double simulated = frames[f]["simulated_seconds"].get<double>();
        const Band b = band(table, f, simulated), whole = extremes(table, f);
        nlohmann::json main = nlohmann::json::array();
        for (const Contribution& c : main_contributors(table, f, 5))
            if (c.share >= 0.01) main.push_back({{"key", c.key}, {"share_of_variance", c.share}});
        frames[f]["uncertainty"] = {{"simulated_seconds_low", b.low},
                                    {"simulated_seconds_high", b.high},
                                    {"every_guess_at_its_worst", {whole.low, whole.high}},
                                    {"main_guesses", main}};
    }
    nlohmann::json guesses = nlohmann::json::array();
    for (const UncertainParameter& p : table.parameters)
        guesses.push_back({{"key", p.key}, {"value", p.value}, {"low", p.low}, {"high", p.high}, {"why", p.why}});
    return {{"bands",
             "95%: every guess spread evenly over its plausible range (in its logarithm where the range stays "
             "above zero), independently; each frame's response measured by re-timing with the guess at either end"},
            {"guesses", guesses},
            {"refused", table.refused},
            {"retimings", table.retimings},
            {"host_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()}};
}

}  // namespace

ScenarioRender render_scenario(const Scenario& scenario, const MachineConfig& config, StagedOutput& output,
                               const ScenarioRenderOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const ImageFormat format = options.format;
    // The lecture pictures' utilisation plot is drawn from the trace's busy spans: record them (into the
    // user's trace if there is one, else into one that keeps nothing else).
    std::optional<TraceRecorder> spans_only;
    TraceRecorder* trace = options.trace;
    if (options.lecture_pictures && trace == nullptr) trace = &spans_only.emplace(0, 0, 0);
    if (options.lecture_pictures) trace->keep_busy_spans(true);
    RenderSession session(scenario, config, trace, format == ImageFormat::Png ? "png" : "exr",
                          options.compare_with_reference);
    nlohmann::json frames = nlohmann::json::array();
    std::vector<std::string> warnings;
    std::vector<std::unique_ptr<KernelFrame>> recorded;  // kept for the bands' re-timing
    for (std::size_t i = 0; i < scenario.frames.size(); ++i) {
        SessionFrame frame = session.render(scenario.frames[i]);
        if (options.lecture_pictures) add_lecture_pictures(frame, session.machine(), *trace, output, warnings);
        for (FrameImage& image : frame.images) output.add_image(image.name, std::move(image.image), format);
        frames.push_back(std::move(frame.record));
        if (options.uncertainty) recorded.push_back(std::move(frame.recorded));
        if (options.progress) options.progress(i + 1, scenario.frames.size());
    }
    std::optional<nlohmann::json> uncertainty;
    if (options.uncertainty) uncertainty = add_frame_bands(config, session.kernel(), recorded, frames);
    const double host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    ScenarioRender result;
    result.stats = session.stats(frames, host_seconds);
    if (uncertainty) result.stats["uncertainty"] = std::move(*uncertainty);
    result.lines = session.summary_lines(frames);
    result.warnings = std::move(warnings);
    output.add_text("stats.json", result.stats.dump(2) + "\n");
    output.add_text("config.json", config.to_json().dump(2) + "\n");
    return result;
}

}  // namespace pp5
