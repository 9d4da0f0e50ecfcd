// `pp5sim compare A B`: two runs' stats.json (or their folders) side by side: every number that
// differs, with its unit, absolute and relative change, largest relative change first. Exit status 0
// when nothing differs beyond --tolerance, 3 when something does (1 stays "internal error" and 2
// "bad input", as for every command), so regression scripts can test it.

#include "frontends/cli/commands.h"
#include "frontends/compare/stats_compare.h"
#include "sim/core/input_error.h"
#include "sim/core/json_input.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

namespace pp5::cli {
namespace {

constexpr int kDiffer = 3;

struct CompareCommandOptions {
    std::string before, after;
    double tolerance = 0.0;
    bool include_host = false;
    std::size_t limit = 0;  // 0: every difference
};

nlohmann::json read_stats(const std::string& given) {
    std::filesystem::path path(given);
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) path /= "stats.json";
    if (!std::filesystem::is_regular_file(path, error))
        throw InputError(path.string(), "compare", "is not a stats.json file or a run folder holding one");
    constexpr std::uintmax_t kMostStatsBytes = std::uintmax_t{1} << 30;
    nlohmann::json json = read_json_file(path, "compare", kMostStatsBytes);
    check_run_stats(json, path.string());
    return json;
}

std::string number(const std::optional<double>& v) { return v ? fmt::format("{:.6g}", *v) : std::string("-"); }

std::string change(const StatDifference& d) {
    const double r = d.relative();
    if (!d.before) return "new";
    if (!d.after) return "gone";
    if (std::isinf(r)) return r > 0 ? "+inf" : "-inf";
    return fmt::format("{:+.2f}%", 100.0 * r);
}

int run_compare(const CompareCommandOptions& o) {
    if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance))
        throw InputError("--tolerance", "--tolerance", "must be a relative change of 0 or more");
    const nlohmann::json a = read_stats(o.before), b = read_stats(o.after);
    const StatsComparison c = compare_stats(a, b, {o.tolerance, o.include_host});
    fmt::print("compare {} -> {}: {} numbers in both, {} differ, {} beyond a relative tolerance of {}\n", o.before,
               o.after, c.compared, c.differences.size(), c.beyond_tolerance, o.tolerance);
    if (!c.differences.empty())
        fmt::print("  {:>10}  {:>12}  {:>12}  {:>12}  {:<9}  {}\n", "relative", "absolute", "before", "after", "unit",
                   "statistic");
    std::size_t shown = 0;
    for (const StatDifference& d : c.differences) {
        if (o.limit > 0 && shown == o.limit) {
            fmt::print("  ... {} more (--limit 0 shows every one)\n", c.differences.size() - shown);
            break;
        }
        fmt::print("  {:>10}  {:>12}  {:>12}  {:>12}  {:<9}  {}\n", change(d),
                   d.before && d.after ? fmt::format("{:+.6g}", d.absolute()) : "-", number(d.before), number(d.after),
                   d.unit.empty() ? "-" : d.unit, d.path);
        ++shown;
    }
    return c.beyond_tolerance > 0 ? kDiffer : 0;
}

}  // namespace

void add_compare_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<CompareCommandOptions>();
    CLI::App* cmd =
        app.add_subcommand("compare", "Two runs' statistics side by side; exit 3 when they differ beyond --tolerance");
    cmd->add_option("before", o->before, "A run's stats.json or its output folder")->required();
    cmd->add_option("after", o->after, "The run to compare with it")->required();
    cmd->add_option("--tolerance", o->tolerance,
                    "Relative change below which two numbers count as the same (0.01 = 1%)")
        ->capture_default_str();
    cmd->add_flag("--include-host", o->include_host,
                  "Compare host_seconds too (this computer's timings, which vary run to run)");
    cmd->add_option("--limit", o->limit, "Show at most this many differences (0: all)")
        ->check(whole_number())
        ->capture_default_str();
    cmd->callback([o, &run] { run = [o] { return run_compare(*o); }; });
}

}  // namespace pp5::cli
