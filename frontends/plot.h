#pragma once
// Plots as PNG, drawn by gnuplot (Debian's gnuplot-nox, cairo terminal): a plot is described here,
// written out as a data file and a gnuplot script (kept beside the PNG, so a user can restyle it), and
// rendered. Nothing is written by this module; the caller stages the three files.

#include <string>
#include <vector>

namespace pp5 {

struct PlotSeries {
    std::string title;
    std::vector<double> x;
    std::vector<double> y;
    std::string style = "points pt 7 ps 1.2";  // gnuplot's "with ..." clause
    // A band around each y (both as long as y, or empty): drawn as error bars, the style's points
    // joined with "yerrorlines" (or shown as "yerrorbars").
    std::vector<double> y_low, y_high;
    bool has_band() const { return !y_low.empty() && y_low.size() == y.size() && y_high.size() == y.size(); }
};

struct PlotSpec {
    std::string title;
    std::string x_label;
    std::string y_label;
    bool log_x = false;
    bool log_y = false;
    std::vector<PlotSeries> series;
    std::vector<std::string> extra_commands;  // e.g. a y = x line: "f(x) = x"
    std::vector<std::string> extra_plots;     // plotted after the series, e.g. "f(x) title 'y = x'"
    int width = 900;
    int height = 650;
};

struct RenderedPlot {
    std::string data;     // NAME.dat
    std::string script;   // NAME.gp
    std::string png;      // NAME.png, bytes; empty when gnuplot could not draw it
    std::string failure;  // why not (gnuplot missing, or its message), when png is empty
};

// Renders `spec`; the script refers to NAME.dat and NAME.png. The data and the script are there
// even when gnuplot is missing or fails, so the work behind a plot is never lost with its picture.
RenderedPlot render_plot(const PlotSpec& spec, const std::string& name);

}  // namespace pp5
