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

std::vector<std::pair<std::string, PlotSpec>> sweep_plots(const SweepResult& result) {
    std::vector<std::pair<std::string, PlotSpec>> plots;
    std::set<std::string> plot_names;
    const nlohmann::json& header = result.header;
    if (header["axes"].empty()) return plots;
    std::string x_key = header.value("plot_x", std::string());
    if (x_key.empty()) x_key = header["axes"][0]["key"].get<std::string>();
    std::vector<std::string> x_values, other_keys;
    for (const auto& axis : header["axes"]) {
        if (axis["key"] == x_key) x_values = axis["values"].get<std::vector<std::string>>();
        else other_keys.push_back(axis["key"].get<std::string>());
    }
    // Numbers along x when every value is one; otherwise the values in order, by name.
    std::vector<double> xs;
    bool numeric = true;
    for (const std::string& v : x_values) {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        numeric = numeric && end != v.c_str() && *end == '\0' && std::isfinite(x);
        xs.push_back(numeric ? x : static_cast<double>(xs.size()));
    }
    if (!numeric)
        for (std::size_t i = 0; i < xs.size(); ++i) xs[i] = static_cast<double>(i);
    const std::size_t grid = [&] {
        std::size_t n = 1;
        for (const auto& axis : header["axes"]) n *= axis["values"].size();
        return n;
    }();
    const std::vector<std::string> keys = parameter_keys(header);
    const bool kernel_varies = std::find(keys.begin(), keys.end(), kSweepKernelKey) != keys.end();
    for (const auto& scenario_json : header["scenarios"]) {
        const std::string scenario = scenario_json.get<std::string>();
        std::string metric = header.value("plot_metric", std::string());
        // Kernels name their figures differently; the frame's simulated time is every kernel's.
        if (metric.empty() && kernel_varies) metric = "simulated_seconds";
        if (metric.empty()) {
            const Kernel* kernel = find_kernel(header["kernels"].value(scenario, std::string()));
            metric =
                kernel != nullptr && !kernel->metrics().empty() ? kernel->metrics().front().name : "simulated_seconds";
        }
        const auto column = std::find_if(result.columns.begin(), result.columns.end(),
                                         [&](const SweepColumn& c) { return c.name == metric; });
        if (column == result.columns.end()) continue;
        const auto c = static_cast<std::size_t>(column - result.columns.begin());
        // With --uncertainty, the metric's band: error bars over the frames' mean band.
        const auto index_of = [&](const std::string& name) -> std::optional<std::size_t> {
            for (std::size_t i = 0; i < result.columns.size(); ++i)
                if (result.columns[i].name == name) return i;
            return std::nullopt;
        };
        const std::optional<std::size_t> low = index_of(metric + "_low"), high = index_of(metric + "_high");
        std::map<std::string, PlotSeries> lines;  // by the other axes' values
        std::vector<std::string> order;
        for (const SweepPointResult& p : result.points) {
            if (p.point.scenario != scenario || !p.error.empty()) continue;
            if (p.point.index % (grid + header["points"].size()) >= grid)
                continue;  // explicit points are not on the grid's lines
            std::string title, x;
            for (const auto& [k, v] : p.point.parameters) {
                if (k == x_key) x = v;
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
            const auto at = std::find(x_values.begin(), x_values.end(), x);
            if (n == 0 || at == x_values.end()) continue;
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
            line.x.push_back(xs[static_cast<std::size_t>(at - x_values.begin())]);
            line.y.push_back(sum / static_cast<double>(n));
            if (banded) {
                line.y_low.push_back(sum_low / static_cast<double>(n));
                line.y_high.push_back(sum_high / static_cast<double>(n));
            }
        }
        if (lines.empty()) continue;
        PlotSpec spec;
        std::string shown_metric = metric, shown_x = x_key;
        std::replace(shown_metric.begin(), shown_metric.end(), '_', ' ');
        std::replace(shown_x.begin(), shown_x.end(), '_', ' ');
        spec.title =
            fmt::format("{}: {} against {} (mean over frames{})", header["name"].get<std::string>(), shown_metric,
                        shown_x, low && high ? ", with its 95% band over the guesses' ranges" : "");
        spec.x_label = shown_x;
        spec.y_label = fmt::format("{} [{}]", shown_metric, column->unit);
        if (numeric && xs.size() > 1) {
            const auto [lo, hi] = std::minmax_element(xs.begin(), xs.end());
            spec.log_x = *lo > 0 && *hi / *lo >= 8;
            const double pad = 0.05 * (*hi - *lo);
            spec.extra_commands.push_back(spec.log_x ? fmt::format("set xrange [{}:{}]", *lo / 1.25, *hi * 1.25)
                                                     : fmt::format("set xrange [{}:{}]", *lo - pad, *hi + pad));
            if (spec.log_x) {
                std::string tics;
                for (std::size_t i = 0; i < xs.size(); ++i)
                    tics += fmt::format("{}\"{}\" {}", i ? ", " : "", x_values[i], xs[i]);
                spec.extra_commands.push_back("set xtics (" + tics + ")");
            }
        } else if (!numeric) {
            std::string tics;
            for (std::size_t i = 0; i < x_values.size(); ++i)
                tics += fmt::format("{}\"{}\" {}", i ? ", " : "", x_values[i], i);
            spec.extra_commands.push_back("set xtics (" + tics + ")");
        }
        // Many lines: the legend goes beside the plot, so it hides no data.
        if (order.size() > 5) {
            spec.extra_commands.push_back("set key outside right top font \",9\"");
            spec.width = 1300;
        }
        for (const std::string& t : order) spec.series.push_back(std::move(lines[t]));
        std::string name = "sweep_" + scenario;
        for (char& ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
        // Names that differ only in the characters replaced ("a b", "a_b") get a number each after the first.
        const std::string base = name;
        for (int copy = 2; !plot_names.insert(name).second; ++copy) name = fmt::format("{}_{}", base, copy);
        plots.emplace_back(name, std::move(spec));
    }
    return plots;
}

}  // namespace pp5
