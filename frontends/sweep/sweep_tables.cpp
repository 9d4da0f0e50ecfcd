#include "frontends/sweep/sweep_tables.h"

#include "frontends/sweep/sweep_json_shape.h"
#include "kernels/registry/registry.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

namespace pp5 {

namespace {

// The parameter columns: the axes' keys, then any other key an explicit point sets.
std::vector<std::string> parameter_keys(const nlohmann::json& header) {
    std::vector<std::string> keys;
    for (const auto& axis : header["axes"]) keys.push_back(axis["key"].get<std::string>());
    for (const auto& point : header["points"])
        for (const auto& [key, value] : point.items())
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    return keys;
}

std::string csv_cell(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string value_text(const nlohmann::json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

[[noreturn]] void not_a_sweep(const std::string& file, const std::string& field, const std::string& why) {
    throw InputError(file, field, why + " (not a pp5sim sweep file?)");
}

}  // namespace

nlohmann::json sweep_to_json(const SweepResult& result, std::optional<Shard> shard) {
    nlohmann::json columns = nlohmann::json::array();
    for (const SweepColumn& c : result.columns)
        columns.push_back({{"name", c.name}, {"unit", c.unit}, {"description", c.description}});
    nlohmann::json points = nlohmann::json::array();
    for (const SweepPointResult& p : result.points) {
        nlohmann::json varied = nlohmann::json::object();
        for (const auto& [k, v] : p.point.parameters) varied[k] = v;
        nlohmann::json frames = nlohmann::json::array();
        for (const SweepFrameResult& f : p.frames) {
            nlohmann::json values = nlohmann::json::object();
            for (std::size_t c = 0; c < result.columns.size(); ++c)
                // A value that is not finite is written as JSON writes it, null (not measured).
                values[result.columns[c].name] =
                    f.values[c] && std::isfinite(*f.values[c]) ? nlohmann::json(*f.values[c]) : nlohmann::json(nullptr);
            frames.push_back({{"frame", f.frame}, {"label", f.label}, {"metrics", values}});
        }
        nlohmann::json point = {{"index", p.point.index},
                                {"scenario", p.point.scenario},
                                {"varied", varied},
                                {"frames", frames},
                                {"parameters", p.parameters}};
        if (!p.error.empty()) point["error"] = p.error;
        points.push_back(std::move(point));
    }
    nlohmann::json out = {{"sweep", result.header}, {"columns", columns}, {"results", points}};
    if (shard) out["shard"] = {{"index", shard->index}, {"count", shard->count}};
    return out;
}

SweepResult sweep_from_json(const nlohmann::json& json, const std::string& file) {
    SweepResult r;
    check_sweep_json_shape(json, file);
    try {
        r.header = json.at("sweep");
        for (const auto& c : json.at("columns")) r.columns.push_back({c.at("name"), c.at("unit"), c.at("description")});
        for (const auto& p : json.at("results")) {
            SweepPointResult point;
            point.point.index = p.at("index").get<std::size_t>();
            point.point.scenario = p.at("scenario").get<std::string>();
            // JSON objects come back sorted by key; the plan's order is the header's.
            for (const std::string& k : parameter_keys(r.header))
                if (p.at("varied").contains(k))
                    point.point.parameters.emplace_back(k, p.at("varied").at(k).get<std::string>());
            point.error = p.value("error", std::string());
            point.parameters = p.at("parameters");
            for (const auto& f : p.at("frames")) {
                SweepFrameResult frame{f.at("frame").get<std::size_t>(), f.at("label").get<std::string>(), {}};
                for (const SweepColumn& c : r.columns) {
                    const nlohmann::json& v = f.at("metrics").at(c.name);
                    frame.values.push_back(v.is_null() ? std::nullopt : std::optional<double>(v.get<double>()));
                }
                point.frames.push_back(std::move(frame));
            }
            r.points.push_back(std::move(point));
        }
    } catch (const nlohmann::json::exception& e) {
        not_a_sweep(file, "results", std::string("is malformed: ") + e.what());
    }
    return r;
}

std::string sweep_to_csv(const SweepResult& result) {
    const std::vector<std::string> keys = parameter_keys(result.header);
    std::string out = "point,scenario";
    const auto append = [](std::string& line, const std::string& cell) {
        line += ',';
        line += cell;
    };
    for (const std::string& k : keys) append(out, csv_cell(k));
    out += ",frame,label,status";
    for (const SweepColumn& c : result.columns) append(out, csv_cell(fmt::format("{} [{}]", c.name, c.unit)));
    out += "\n";
    for (const SweepPointResult& p : result.points) {
        std::string lead = fmt::format("{},{}", p.point.index, csv_cell(p.point.scenario));
        for (const std::string& k : keys)
            append(lead, csv_cell(p.parameters.contains(k) ? value_text(p.parameters[k]) : std::string()));
        if (!p.error.empty()) {
            out += lead + ",,," + csv_cell("error: " + p.error) + std::string(result.columns.size(), ',') + "\n";
            continue;
        }
        for (const SweepFrameResult& f : p.frames) {
            out += lead + fmt::format(",{},{},ok", f.frame, csv_cell(f.label));
            for (const std::optional<double>& v : f.values) out += v ? fmt::format(",{}", *v) : std::string(",");
            out += "\n";
        }
    }
    return out;
}

std::string shard_file_name(const Shard& shard) { return fmt::format("shard-{}-of-{}.json", shard.index, shard.count); }

SweepResult merge_sweep_shards(const std::vector<std::pair<std::string, nlohmann::json>>& shards) {
    if (shards.empty()) throw InputError("--merge", "--merge", "found no shard-K-of-N.json files to merge");
    SweepResult merged;
    std::optional<std::size_t> count;
    std::set<std::size_t> seen_shards, seen_points;
    for (const auto& [file, json] : shards) {
        SweepResult part = sweep_from_json(json, file);
        if (!json.contains("shard")) throw InputError(file, "shard", "is missing: this is not a shard's file");
        const auto index = json["shard"]["index"].get<std::size_t>(), n = json["shard"]["count"].get<std::size_t>();
        if (!count) {
            count = n;
            merged.header = part.header;
            merged.columns = part.columns;
        } else if (n != *count) {
            throw InputError(file, "shard.count",
                             fmt::format("is {} but {} was split {} ways", n, shards.front().first, *count));
        } else if (part.header != merged.header) {
            throw InputError(file, "sweep",
                             "differs from " + shards.front().first + "'s: the shards are of different sweeps");
        }
        if (index >= n || !seen_shards.insert(index).second)
            throw InputError(file, "shard.index",
                             fmt::format("shard {} of {} is given twice or is out of range", index, n));
        for (SweepPointResult& p : part.points) {
            if (p.point.index % n != index || !seen_points.insert(p.point.index).second)
                throw InputError(file, "results",
                                 fmt::format("point {} does not belong to shard {} of {}", p.point.index, index, n));
            merged.points.push_back(std::move(p));
        }
    }
    for (std::size_t k = 0; k < *count; ++k)
        if (!seen_shards.count(k))
            throw InputError("--merge", "--merge",
                             fmt::format("{} is missing: every one of the {} shards is needed",
                                         shard_file_name({k, *count}), *count));
    const auto total = merged.header.at("total_points").get<std::size_t>();
    if (merged.points.size() != total)
        throw InputError("--merge", "--merge",
                         fmt::format("the shards hold {} points of {}", merged.points.size(), total));
    std::sort(merged.points.begin(), merged.points.end(),
              [](const SweepPointResult& a, const SweepPointResult& b) { return a.point.index < b.point.index; });
    return merged;
}

namespace {

// The axis a sweep's plots run along (the header's plot_x, else its first axis): its values, as numbers
// when every value is one, otherwise in order, by name.
struct PlotAxis {
    std::string key;
    std::vector<std::string> values;
    std::vector<double> positions;
    bool numeric = true;
};

PlotAxis plot_axis(const nlohmann::json& header) {
    PlotAxis axis;
    axis.key = header.value("plot_x", std::string());
    if (axis.key.empty()) axis.key = header["axes"][0]["key"].get<std::string>();
    for (const auto& a : header["axes"])
        if (a["key"] == axis.key) axis.values = a["values"].get<std::vector<std::string>>();
    for (const std::string& v : axis.values) {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        axis.numeric = axis.numeric && end != v.c_str() && *end == '\0' && std::isfinite(x);
        axis.positions.push_back(axis.numeric ? x : static_cast<double>(axis.positions.size()));
    }
    if (!axis.numeric)
        for (std::size_t i = 0; i < axis.positions.size(); ++i) axis.positions[i] = static_cast<double>(i);
    return axis;
}

// The figure a scenario's plot shows: the header's plot_metric, else its kernel's first metric; the
// frame's simulated time when kernels vary (they name their figures differently) or have none.
std::string plot_metric(const nlohmann::json& header, const std::string& scenario, bool kernel_varies) {
    std::string metric = header.value("plot_metric", std::string());
    if (!metric.empty()) return metric;
    if (kernel_varies) return "simulated_seconds";
    const Kernel* kernel = find_kernel(header["kernels"].value(scenario, std::string()));
    return kernel != nullptr && !kernel->metrics().empty() ? kernel->metrics().front().name : "simulated_seconds";
}

std::optional<std::size_t> column_index(const SweepResult& result, const std::string& name) {
    for (std::size_t i = 0; i < result.columns.size(); ++i)
        if (result.columns[i].name == name) return i;
    return std::nullopt;
}

// One line per setting of the other axes, in the order first met: each grid point's metric averaged
// over its frames, and with --uncertainty (columns `low` and `high`) its band as error bars.
std::vector<PlotSeries> metric_lines(const SweepResult& result, const std::string& scenario, const PlotAxis& axis,
                                     std::size_t c, std::optional<std::size_t> low, std::optional<std::size_t> high) {
    const nlohmann::json& header = result.header;
    std::size_t grid = 1;
    for (const auto& a : header["axes"]) grid *= a["values"].size();
    std::map<std::string, PlotSeries> lines;  // by the other axes' values
    std::vector<std::string> order;
    for (const SweepPointResult& p : result.points) {
        if (p.point.scenario != scenario || !p.error.empty()) continue;
        if (p.point.index % (grid + header["points"].size()) >= grid)
            continue;  // explicit points are not on the grid's lines
        std::string title, x;
        for (const auto& [k, v] : p.point.parameters) {
            if (k == axis.key) x = v;
            else title += (title.empty() ? "" : ", ") + k + " = " + v;
        }
        double sum = 0, sum_low = 0, sum_high = 0;
        std::size_t n = 0;
        bool banded = low && high;
        for (const SweepFrameResult& f : p.frames)
            if (f.values[c]) {
                sum += *f.values[c], ++n;
                banded = banded && f.values[*low] && f.values[*high];
                if (banded) sum_low += *f.values[*low], sum_high += *f.values[*high];
            }
        const auto at = std::find(axis.values.begin(), axis.values.end(), x);
        if (n == 0 || at == axis.values.end()) continue;
        if (!lines.count(title)) {
            order.push_back(title);
            std::string shown = title.empty() ? scenario : title;
            std::replace(shown.begin(), shown.end(), '_', ' ');  // gnuplot reads _ as a subscript
            const int point_type = 5 + 2 * static_cast<int>(order.size() % 4);
            lines[title] = PlotSeries{
                shown, {}, {}, fmt::format("{} pt {} lw 2", banded ? "yerrorlines" : "linespoints", point_type),
                {},    {}};
        }
        PlotSeries& line = lines[title];
        line.x.push_back(axis.positions[static_cast<std::size_t>(at - axis.values.begin())]);
        line.y.push_back(sum / static_cast<double>(n));
        if (banded) {
            line.y_low.push_back(sum_low / static_cast<double>(n));
            line.y_high.push_back(sum_high / static_cast<double>(n));
        }
    }
    std::vector<PlotSeries> ordered;
    for (const std::string& t : order) ordered.push_back(std::move(lines[t]));
    return ordered;
}

// The x axis's range and tics: a logarithmic axis when numbers span a factor of 8 or more, names at
// their positions when the values are not numbers.
void set_x_axis(PlotSpec& spec, const PlotAxis& axis) {
    const std::vector<double>& xs = axis.positions;
    if (axis.numeric && xs.size() > 1) {
        const auto [lo, hi] = std::minmax_element(xs.begin(), xs.end());
        spec.log_x = *lo > 0 && *hi / *lo >= 8;
        const double pad = 0.05 * (*hi - *lo);
        spec.extra_commands.push_back(spec.log_x ? fmt::format("set xrange [{}:{}]", *lo / 1.25, *hi * 1.25)
                                                 : fmt::format("set xrange [{}:{}]", *lo - pad, *hi + pad));
        if (spec.log_x) {
            std::string tics;
            for (std::size_t i = 0; i < xs.size(); ++i)
                tics += fmt::format("{}\"{}\" {}", i ? ", " : "", axis.values[i], xs[i]);
            spec.extra_commands.push_back("set xtics (" + tics + ")");
        }
    } else if (!axis.numeric) {
        std::string tics;
        for (std::size_t i = 0; i < axis.values.size(); ++i)
            tics += fmt::format("{}\"{}\" {}", i ? ", " : "", axis.values[i], i);
        spec.extra_commands.push_back("set xtics (" + tics + ")");
    }
}

// "sweep_<scenario>" with every character but letters, digits, - and _ replaced; names that differ
// only in the characters replaced ("a b", "a_b") get a number each after the first.
std::string unique_plot_name(const std::string& scenario, std::set<std::string>& taken) {
    std::string name = "sweep_" + scenario;
    for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
    const std::string base = name;
    for (int copy = 2; !taken.insert(name).second; ++copy) name = fmt::format("{}_{}", base, copy);
    return name;
}

}  // namespace

std::vector<std::pair<std::string, PlotSpec>> sweep_plots(const SweepResult& result) {
    std::vector<std::pair<std::string, PlotSpec>> plots;
    std::set<std::string> plot_names;
    const nlohmann::json& header = result.header;
    if (header["axes"].empty()) return plots;
    const PlotAxis axis = plot_axis(header);
    const std::vector<std::string> keys = parameter_keys(header);
    const bool kernel_varies = std::find(keys.begin(), keys.end(), kSweepKernelKey) != keys.end();
    for (const auto& scenario_json : header["scenarios"]) {
        const std::string scenario = scenario_json.get<std::string>();
        const std::string metric = plot_metric(header, scenario, kernel_varies);
        const std::optional<std::size_t> c = column_index(result, metric);
        if (!c) continue;
        // With --uncertainty, the metric's band: error bars over the frames' mean band.
        const std::optional<std::size_t> low = column_index(result, metric + "_low"),
                                         high = column_index(result, metric + "_high");
        std::vector<PlotSeries> lines = metric_lines(result, scenario, axis, *c, low, high);
        if (lines.empty()) continue;
        PlotSpec spec;
        std::string shown_metric = metric, shown_x = axis.key;
        std::replace(shown_metric.begin(), shown_metric.end(), '_', ' ');
        std::replace(shown_x.begin(), shown_x.end(), '_', ' ');
        spec.title =
            fmt::format("{}: {} against {} (mean over frames{})", header["name"].get<std::string>(), shown_metric,
                        shown_x, low && high ? ", with its 95% band over the guesses' ranges" : "");
        spec.x_label = shown_x;
        spec.y_label = fmt::format("{} [{}]", shown_metric, result.columns[*c].unit);
        set_x_axis(spec, axis);
        // Many lines: the legend goes beside the plot, so it hides no data.
        if (lines.size() > 5) {
            spec.extra_commands.push_back("set key outside right top font \",9\"");
            spec.width = 1300;
        }
        spec.series = std::move(lines);
        plots.emplace_back(unique_plot_name(scenario, plot_names), std::move(spec));
    }
    return plots;
}

}  // namespace pp5
