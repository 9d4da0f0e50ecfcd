#include "frontends/render_scenario.h"

#include "frontends/render_session.h"

#include <chrono>

namespace pp5 {

ScenarioRender render_scenario(const Scenario& scenario, const MachineConfig& config, StagedOutput& output,
                               const ScenarioRenderOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const ImageFormat format = options.format;
    RenderSession session(scenario, config, options.trace, format == ImageFormat::Png ? "png" : "exr");
    nlohmann::json frames = nlohmann::json::array();
    for (std::size_t i = 0; i < scenario.frames.size(); ++i) {
        SessionFrame frame = session.render(scenario.frames[i]);
        for (FrameImage& image : frame.images) output.add_image(image.name, std::move(image.image), format);
        frames.push_back(std::move(frame.record));
        if (options.progress) options.progress(i + 1, scenario.frames.size());
    }
    const double host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    ScenarioRender result;
    result.stats = session.stats(frames, host_seconds);
    result.lines = session.summary_lines(frames);
    output.add_text("stats.json", result.stats.dump(2) + "\n");
    output.add_text("config.json", config.to_json().dump(2) + "\n");
    return result;
}

}  // namespace pp5
