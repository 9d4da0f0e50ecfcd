#include "frontends/compare/stats_compare.h"

#include "sim/core/input_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace pp5 {

namespace {

struct Leaf {
    double value;
    std::string unit;
};

// Every number under `node`. A statistic written as {value, unit, description} is one number at its
// own path, with its unit; a histogram's value holds its bounds and sum in that unit, and counts.
void collect(const nlohmann::json& node, const std::string& path, const std::string& unit,
             const CompareOptions& options, std::map<std::string, Leaf>& out) {
    if (node.is_object()) {
        if (node.contains("value") && node.contains("unit") && node["unit"].is_string()) {
            const nlohmann::json& value = node["value"];
            if (value.is_number()) {
                out[path] = {value.get<double>(), node["unit"].get<std::string>()};
            } else {
                for (const auto& [key, child] : value.items()) {
                    const bool in_unit = key == "bounds" || key == "sum";
                    collect(child, path + "/" + key, in_unit ? node["unit"].get<std::string>() : "count", options, out);
                }
            }
            return;
        }
        for (const auto& [key, child] : node.items()) {
            if (key == "host_seconds" && !options.include_host) continue;
            collect(child, path.empty() ? key : path + "/" + key, unit, options, out);
        }
    } else if (node.is_array()) {
        for (std::size_t i = 0; i < node.size(); ++i)
            collect(node[i], path + "/" + std::to_string(i), unit, options, out);
    } else if (node.is_number()) {
        // Kernels' frame records name their units in their keys (a list's items in the list's).
        std::string key = path;
        while (key.find('/') != std::string::npos &&
               key.substr(key.rfind('/') + 1).find_first_not_of("0123456789") == std::string::npos)
            key.resize(key.rfind('/'));
        key = key.substr(key.rfind('/') + 1);
        const std::string named = key.ends_with("_seconds") || key == "seconds" ? "s"
                                  : key.ends_with("_db")                        ? "dB"
                                                                                : "";
        out[path] = {node.get<double>(), !unit.empty() ? unit : named};
    }
}

}  // namespace

double StatDifference::relative() const {
    if (!before || !after) return std::numeric_limits<double>::infinity();
    if (*before == *after) return 0.0;
    if (*before == 0.0) return std::copysign(std::numeric_limits<double>::infinity(), *after);
    return (*after - *before) / std::abs(*before);
}

StatsComparison compare_stats(const nlohmann::json& before, const nlohmann::json& after,
                              const CompareOptions& options) {
    std::map<std::string, Leaf> a, b;
    collect(before, "", "", options, a);
    collect(after, "", "", options, b);
    StatsComparison out;
    for (const auto& [path, leaf] : a) {
        const auto other = b.find(path);
        if (other == b.end()) {
            out.differences.push_back({path, leaf.unit, leaf.value, std::nullopt});
            continue;
        }
        ++out.compared;
        if (other->second.value != leaf.value)
            out.differences.push_back(
                {path, leaf.unit.empty() ? other->second.unit : leaf.unit, leaf.value, other->second.value});
    }
    for (const auto& [path, leaf] : b)
        if (!a.count(path)) out.differences.push_back({path, leaf.unit, std::nullopt, leaf.value});
    // Numbers in both first, largest relative change first (a change from zero is infinite); then
    // those only one run has (a GP the other machine lacks), by path.
    std::stable_sort(out.differences.begin(), out.differences.end(),
                     [](const StatDifference& x, const StatDifference& y) {
                         const bool both_x = x.before && x.after, both_y = y.before && y.after;
                         if (both_x != both_y) return both_x;
                         const double rx = std::abs(x.relative()), ry = std::abs(y.relative());
                         return rx != ry ? rx > ry : x.path < y.path;
                     });
    for (const StatDifference& d : out.differences) out.beyond_tolerance += std::abs(d.relative()) > options.tolerance;
    return out;
}

void check_run_stats(const nlohmann::json& json, const std::string& file) {
    const auto refuse = [&](const std::string& field, const std::string& why) {
        throw InputError(file, field, why + ": compare takes two runs' stats.json, as `pp5sim render` writes them");
    };
    if (!json.is_object()) refuse("compare", "is not a JSON object");
    if (json.contains("sweep") && json.contains("results"))
        refuse("compare", "is a sweep's results (sweep.json or a shard), not a run's statistics");
    for (const char* table : {"summary", "components"})
        if (!json.contains(table) || !json[table].is_object()) refuse(table, "is missing or not an object");
    if (!json.contains("frames") || !json["frames"].is_array()) refuse("frames", "is missing or not a list");
    const nlohmann::json& summary = json["summary"];
    for (const char* text : {"scenario", "kernel"})
        if (!summary.contains(text) || !summary[text].is_string())
            refuse(std::string("summary.") + text, "is missing or not text");
    if (!summary.contains("simulated_seconds") || !summary["simulated_seconds"].is_array())
        refuse("summary.simulated_seconds", "is missing or not a list of frame times");
}

}  // namespace pp5
