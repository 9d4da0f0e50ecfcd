#include "frontends/staged_plot.h"

#include <fmt/format.h>

namespace pp5 {

std::optional<std::string> stage_plot(StagedOutput& output, const PlotSpec& spec, const std::string& name) {
    RenderedPlot plot = render_plot(spec, name);
    output.add_text(name + ".dat", std::move(plot.data));
    output.add_text(name + ".gp", std::move(plot.script));
    if (plot.png.empty())
        return fmt::format("warning: {}.png not drawn, {}; its data and gnuplot script are in {}.dat and {}.gp", name,
                           plot.failure, name, name);
    output.add_text(name + ".png", std::move(plot.png));
    return std::nullopt;
}

}  // namespace pp5
