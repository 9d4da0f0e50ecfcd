#include "frontends/plot.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace pp5 {

namespace {

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) out += c == '"' ? std::string("\\\"") : std::string(1, c);
    return out + "\"";
}

std::string read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

RenderedPlot render_plot(const PlotSpec& spec, const std::string& name) {
    RenderedPlot plot;
    // One block per series, separated by two blank lines (gnuplot's "index").
    for (const PlotSeries& series : spec.series) {
        plot.data += "# " + series.title + "\n";
        for (std::size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
            plot.data += fmt::format("{:.9g} {:.9g}", series.x[i], series.y[i]);
            if (series.has_band()) plot.data += fmt::format(" {:.9g} {:.9g}", series.y_low[i], series.y_high[i]);
            plot.data += "\n";
        }
        plot.data += "\n\n";
    }
    std::string s;
    s += fmt::format("set terminal pngcairo size {},{} enhanced font 'DejaVu Sans,11'\n", spec.width, spec.height);
    s += fmt::format("set output {}\n", quoted(name + ".png"));
    s += fmt::format("set title {}\nset xlabel {}\nset ylabel {}\n", quoted(spec.title), quoted(spec.x_label),
                     quoted(spec.y_label));
    s += "set grid\nset key top left box opaque\n";
    if (spec.log_x) s += "set logscale x\n";
    if (spec.log_y) s += "set logscale y\n";
    for (const std::string& c : spec.extra_commands) s += c + "\n";
    std::string plots;
    for (std::size_t i = 0; i < spec.series.size(); ++i) {
        plots += fmt::format("{}{} index {} using {} with {} title {}", plots.empty() ? "" : ", \\\n     ",
                             quoted(name + ".dat"), i, spec.series[i].has_band() ? "1:2:3:4" : "1:2",
                             spec.series[i].style, quoted(spec.series[i].title));
    }
    for (const std::string& p : spec.extra_plots) plots += (plots.empty() ? "" : ", \\\n     ") + p;
    s += "plot " + plots + "\n";
    plot.script = s;

    // Render in a private directory, then read the picture back.
    std::random_device seed;
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / fmt::format("pp5sim-plot-{:x}", seed());
    std::filesystem::create_directories(dir);
    struct Cleanup {
        std::filesystem::path dir;
        ~Cleanup() {
            std::error_code ignored;
            std::filesystem::remove_all(dir, ignored);
        }
    } cleanup{dir};
    std::ofstream(dir / (name + ".dat"), std::ios::binary) << plot.data;
    std::ofstream(dir / (name + ".gp"), std::ios::binary) << plot.script;
    const std::string command =
        fmt::format("cd {} && gnuplot {} > gnuplot.log 2>&1", quoted(dir.string()), quoted(name + ".gp"));
    const int status = std::system(command.c_str());
    if (status != 0 || !std::filesystem::exists(dir / (name + ".png"))) {
        std::string log = read_all(dir / "gnuplot.log");
        while (!log.empty() && (log.back() == '\n' || log.back() == ' ')) log.pop_back();
        plot.failure =
            fmt::format("gnuplot could not draw it (is gnuplot-nox installed? .ci/install-deps installs it){}",
                        log.empty() ? std::string() : ": " + log);
        return plot;
    }
    plot.png = read_all(dir / (name + ".png"));
    return plot;
}

}  // namespace pp5
