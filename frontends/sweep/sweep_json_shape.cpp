#include "frontends/sweep/sweep_json_shape.h"

#include "frontends/sweep/sweep_spec.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

namespace pp5 {

namespace {

using nlohmann::json;

// Typed reads of one file's members, each naming its field path when it fails.
class ShapeReader {
public:
    explicit ShapeReader(const std::string& file) : file_(file) {}

    [[noreturn]] void fail(const std::string& field, const std::string& why) const {
        throw InputError(file_, field, why + " (not a pp5sim sweep file?)");
    }

    const json& member(const json& object, const std::string& path, const std::string& key) const {
        const auto it = object.find(key);
        if (it == object.end()) fail(join(path, key), "is missing");
        return *it;
    }
    const json& object(const json& parent, const std::string& path, const std::string& key) const {
        const json& value = member(parent, path, key);
        if (!value.is_object()) fail(join(path, key), "must be an object");
        return value;
    }
    const json& array(const json& parent, const std::string& path, const std::string& key) const {
        const json& value = member(parent, path, key);
        if (!value.is_array()) fail(join(path, key), "must be a list");
        return value;
    }
    void text(const json& parent, const std::string& path, const std::string& key) const {
        if (!member(parent, path, key).is_string()) fail(join(path, key), "must be text");
    }
    std::size_t whole_number(const json& parent, const std::string& path, const std::string& key,
                             std::size_t most) const {
        const json& value = member(parent, path, key);
        // Integers built in memory are signed; read from a file, the ones at or above zero are unsigned.
        const bool whole = value.is_number_unsigned() || (value.is_number_integer() && value.get<std::int64_t>() >= 0);
        if (!whole || value.get<std::uint64_t>() > most)
            fail(join(path, key), fmt::format("must be a whole number from 0 to {}", most));
        return value.get<std::size_t>();
    }
    void texts(const json& list, const std::string& path) const {
        for (std::size_t i = 0; i < list.size(); ++i)
            if (!list[i].is_string()) fail(fmt::format("{}[{}]", path, i), "must be text");
    }
    void text_values(const json& object, const std::string& path) const {
        for (const auto& [key, value] : object.items())
            if (!value.is_string()) fail(join(path, key), "must be text");
    }

    static std::string join(const std::string& path, const std::string& key) {
        return path.empty() ? key : path + "." + key;
    }

private:
    const std::string& file_;
};

// The header ("sweep"): what was swept. Returns its total point count.
std::size_t check_header(const ShapeReader& read, const json& header) {
    for (const char* key : {"name", "description", "machine", "plot_x", "plot_metric"}) read.text(header, "sweep", key);
    const json& scenarios = read.array(header, "sweep", "scenarios");
    if (scenarios.empty()) read.fail("sweep.scenarios", "needs at least one scenario");
    read.texts(scenarios, "sweep.scenarios");
    read.texts(read.array(header, "sweep", "set"), "sweep.set");
    read.whole_number(header, "sweep", "frames", 100000);
    read.text_values(read.object(header, "sweep", "kernels"), "sweep.kernels");

    const json& axes = read.array(header, "sweep", "axes");
    std::size_t grid = axes.empty() ? 0 : 1;
    for (std::size_t a = 0; a < axes.size(); ++a) {
        const std::string path = fmt::format("sweep.axes[{}]", a);
        if (!axes[a].is_object()) read.fail(path, "must be an object with key and values");
        read.text(axes[a], path, "key");
        const json& values = read.array(axes[a], path, "values");
        if (values.empty()) read.fail(path + ".values", "needs at least one value");
        read.texts(values, path + ".values");
        grid = std::min(grid * std::min(values.size(), kMaxSweepPoints + 1), kMaxSweepPoints + 1);
    }
    const json& points = read.array(header, "sweep", "points");
    for (std::size_t p = 0; p < points.size(); ++p) {
        const std::string path = fmt::format("sweep.points[{}]", p);
        if (!points[p].is_object()) read.fail(path, "must be an object of parameter = value");
        read.text_values(points[p], path);
    }
    const std::size_t total = read.whole_number(header, "sweep", "total_points", kMaxSweepPoints);
    const std::size_t planned = std::min(grid + points.size(), kMaxSweepPoints + 1) * scenarios.size();
    if (planned != total)
        read.fail("sweep.total_points",
                  fmt::format("is {}, but the scenarios, axes and points make {}", total, planned));
    if (header.contains("uncertainty") && !header["uncertainty"].is_object())
        read.fail("sweep.uncertainty", "must be an object");
    return total;
}

// One point's results: its frames' metrics, one per column (a number, or null when not measured).
void check_result(const ShapeReader& read, const json& result, const std::string& path, std::size_t total,
                  const std::set<std::string>& scenarios, const std::vector<std::string>& columns) {
    if (!result.is_object()) read.fail(path, "must be an object");
    if (read.whole_number(result, path, "index", kMaxSweepPoints) >= total)
        read.fail(path + ".index", fmt::format("must be below the sweep's {} points", total));
    read.text(result, path, "scenario");
    if (!scenarios.count(result["scenario"].get<std::string>()))
        read.fail(path + ".scenario", "is not one of the sweep's scenarios");
    read.text_values(read.object(result, path, "varied"), path + ".varied");
    read.object(result, path, "parameters");
    if (result.contains("error")) read.text(result, path, "error");
    const json& frames = read.array(result, path, "frames");
    for (std::size_t f = 0; f < frames.size(); ++f) {
        const std::string frame_path = fmt::format("{}.frames[{}]", path, f);
        if (!frames[f].is_object()) read.fail(frame_path, "must be an object");
        read.whole_number(frames[f], frame_path, "frame", 100000);
        read.text(frames[f], frame_path, "label");
        const json& metrics = read.object(frames[f], frame_path, "metrics");
        for (const std::string& column : columns) {
            const json& value = read.member(metrics, frame_path + ".metrics", column);
            if (!value.is_null() && !(value.is_number() && std::isfinite(value.get<double>())))
                read.fail(frame_path + ".metrics." + column, "must be a finite number or null");
        }
    }
}

}  // namespace

void check_sweep_json_shape(const json& document, const std::string& file) {
    const ShapeReader read(file);
    if (!document.is_object()) read.fail("sweep", "the file must hold a JSON object with sweep, columns and results");
    const std::size_t total = check_header(read, read.object(document, "", "sweep"));

    const json& columns = read.array(document, "", "columns");
    std::vector<std::string> column_names;
    std::set<std::string> seen_columns;
    for (std::size_t c = 0; c < columns.size(); ++c) {
        const std::string path = fmt::format("columns[{}]", c);
        if (!columns[c].is_object()) read.fail(path, "must be an object with name, unit and description");
        for (const char* key : {"name", "unit", "description"}) read.text(columns[c], path, key);
        column_names.push_back(columns[c]["name"].get<std::string>());
        if (!seen_columns.insert(column_names.back()).second) read.fail(path + ".name", "repeats an earlier column");
    }

    std::set<std::string> scenarios;
    for (const json& scenario : document["sweep"]["scenarios"]) scenarios.insert(scenario.get<std::string>());
    const json& results = read.array(document, "", "results");
    if (results.size() > total)
        read.fail("results", fmt::format("holds {} points, more than the sweep's {}", results.size(), total));
    for (std::size_t r = 0; r < results.size(); ++r)
        check_result(read, results[r], fmt::format("results[{}]", r), total, scenarios, column_names);

    if (document.contains("shard")) {
        const json& shard = read.object(document, "", "shard");
        const std::size_t count = read.whole_number(shard, "shard", "count", kMaxSweepPoints);
        if (count == 0) read.fail("shard.count", "must be at least 1");
        if (read.whole_number(shard, "shard", "index", kMaxSweepPoints) >= count)
            read.fail("shard.index", fmt::format("must be below shard.count ({})", count));
    }
}

}  // namespace pp5
