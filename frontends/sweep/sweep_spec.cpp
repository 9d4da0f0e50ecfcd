#include "frontends/sweep/sweep_spec.h"

#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"
#include "sim/core/named_file.h"
#include "sim/core/toml_file.h"
#include "sim/core/toml_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>

namespace pp5 {

namespace {

constexpr int kMostNesting = 8;  // gp.cache.bits is two levels; deeper is a mistake, not a key

// A TOML value as --set would take it.
std::string as_override_text(const toml::node& node, const std::string& file, const std::string& field) {
    if (const auto* i = node.as_integer()) return fmt::format("{}", i->get());
    if (const auto* d = node.as_floating_point()) return fmt::format("{}", d->get());
    if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* s = node.as_string()) return s->get();
    throw InputError(file, field, "must be a number, a boolean or a string");
}

// Flattens a table of parameters (quoted dotted keys, or nested tables) into (key, node, line).
struct Leaf {
    std::string key;
    const toml::node* node;
    std::uint32_t line;
};
void flatten(const toml::table& table, const std::string& prefix, int depth, const std::string& file,
             const std::string& field, std::vector<Leaf>& out) {
    if (depth > kMostNesting)
        throw InputError(file, field + prefix,
                         fmt::format("nests deeper than {} levels; no parameter does", kMostNesting));
    for (const auto& [k, v] : table) {
        const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
        if (const toml::table* inner = v.as_table()) {
            flatten(*inner, key, depth + 1, file, field, out);
        } else {
            out.push_back({key, &v, v.source().begin.line});
        }
    }
}

// Keys in the order the file gives them (toml++ keeps tables sorted).
std::vector<Leaf> leaves_in_file_order(const toml::table& table, const std::string& file, const std::string& field) {
    std::vector<Leaf> leaves;
    flatten(table, "", 0, file, field, leaves);
    std::stable_sort(leaves.begin(), leaves.end(), [](const Leaf& a, const Leaf& b) { return a.line < b.line; });
    return leaves;
}

}  // namespace

// Where sweep files are found by name: $PP5SIM_SWEEPS, then the source tree's traces/sweeps.
static NamedFileSearch sweep_search() {
#ifdef PP5_SWEEPS_DIR
    const char* builtin = PP5_SWEEPS_DIR;
#else
    const char* builtin = nullptr;
#endif
    return {"PP5SIM_SWEEPS", builtin, "sweep", "traces/sweeps/*.toml"};
}

std::filesystem::path resolve_sweep_file(const std::string& name_or_path) {
    return resolve_named_file(name_or_path, sweep_search());
}

std::vector<std::filesystem::path> shipped_sweep_files() { return list_named_files(sweep_search()); }

SweepSpec load_sweep_file(const std::filesystem::path& path) {
    const std::string file = path.string();
    const toml::table root = read_toml_file(file);
    SweepSpec spec;
    spec.file = file;
    spec.name = path.stem().string();
    TomlTable top(&root, "", file);
    top.allow({"vary", "points"});  // read below, as parameter tables
    if (!top.has("sweep"))
        top.fail("sweep", "is missing: a sweep file starts with a [sweep] table naming its scenarios");
    TomlTable head = top.sub("sweep");
    if (const auto name = head.text("name"); name && !name->empty()) spec.name = *name;
    spec.description = head.text("description").value_or("");
    spec.scenarios = head.text_list("scenarios").value_or(std::vector<std::string>{});
    if (const auto machine = head.text("machine"); machine && !machine->empty()) spec.machine = *machine;
    spec.fixed = head.text_list("set").value_or(std::vector<std::string>{});
    spec.uncertainty = head.boolean("uncertainty").value_or(false);
    spec.frames = static_cast<int>(head.integer("frames", 0, 100000).value_or(0));  // 0: all
    spec.plot_x = head.text("plot_x").value_or("");
    spec.plot_metric = head.text("plot_metric").value_or("");
    head.finish();
    top.finish();

    if (const toml::node* vary = root.get("vary")) {
        const toml::table* table = vary->as_table();
        if (table == nullptr) throw InputError(file, "vary", "must be a table of parameter = [values]");
        for (const Leaf& leaf : leaves_in_file_order(*table, file, "vary.")) {
            const std::string field = "vary." + leaf.key;
            const toml::array* values = leaf.node->as_array();
            if (values == nullptr) throw InputError(file, field, "must be a list of values");
            SweepAxis axis{leaf.key, {}};
            for (std::size_t i = 0; i < values->size(); ++i)
                axis.values.push_back(as_override_text((*values)[i], file, fmt::format("{}[{}]", field, i)));
            spec.axes.push_back(std::move(axis));
        }
    }
    if (const toml::node* points = root.get("points")) {
        const toml::array* rows = points->as_array();
        if (rows == nullptr) throw InputError(file, "points", "must be [[points]] tables of parameter = value");
        for (std::size_t i = 0; i < rows->size(); ++i) {
            const std::string field = fmt::format("points[{}].", i);
            const toml::table* row = (*rows)[i].as_table();
            if (row == nullptr)
                throw InputError(file, field.substr(0, field.size() - 1), "must be a table of parameter = value");
            SweepAssignment point;
            for (const Leaf& leaf : leaves_in_file_order(*row, file, field))
                point.emplace_back(leaf.key, as_override_text(*leaf.node, file, field + leaf.key));
            spec.points.push_back(std::move(point));
        }
    }
    check_sweep_spec(spec);
    return spec;
}

SweepAxis parse_vary_option(const std::string& text) {
    const auto fail = [&](const std::string& why) { throw InputError("--vary", "--vary", "\"" + text + "\": " + why); };
    const auto equals = text.find('=');
    if (equals == std::string::npos || equals == 0) fail("expected key=v1,v2,... (e.g. gp.count=8,16,32)");
    SweepAxis axis{text.substr(0, equals), {}};
    const std::string list = text.substr(equals + 1);
    for (std::size_t at = 0, next; at <= list.size(); at = next + 1) {
        next = std::min(list.find(',', at), list.size());
        const std::string value = list.substr(at, next - at);
        if (value.empty()) fail("an empty value");
        axis.values.push_back(value);
    }
    return axis;
}

void check_sweep_spec(const SweepSpec& spec) {
    const std::string& file = spec.file;
    // It names the output folder, out/sweeps/<name>.
    if (const std::string problem = output_name_problem(spec.name); !problem.empty())
        throw InputError(file, "sweep.name", problem);
    if (spec.scenarios.empty()) throw InputError(file, "sweep.scenarios", "needs at least one scenario");
    // A scenario's rows and plot are known by its name, so two entries may not name the same one.
    std::map<std::string, std::size_t> entry_of_name;
    for (std::size_t i = 0; i < spec.scenarios.size(); ++i) {
        const std::string field = fmt::format("sweep.scenarios[{}]", i);
        std::string name;
        try {
            name = load_scenario(resolve_scenario_file(spec.scenarios[i])).name;
        } catch (const InputError& e) {
            throw InputError(file, field, std::string("\"") + spec.scenarios[i] + "\": " + e.what());
        }
        if (const auto [earlier, added] = entry_of_name.emplace(name, i); !added)
            throw InputError(file, field,
                             fmt::format("\"{}\" is scenario {}, which sweep.scenarios[{}] already names",
                                         spec.scenarios[i], name, earlier->second));
    }
    try {
        (void)load_run_config(spec.machine, spec.fixed);
    } catch (const InputError& e) {
        throw InputError(file, "sweep.machine", e.what());
    }
    // Every value is one its parameter takes, and no key is both fixed and varied, or varied twice.
    std::set<std::string> keys;
    for (const std::string& f : spec.fixed) keys.insert(f.substr(0, f.find('=')));
    const auto check_value = [&](const std::string& key, const std::string& value, const std::string& field) {
        if (key == kSweepKernelKey) {
            if (find_kernel(value) == nullptr)
                throw InputError(file, field, "\"" + value + "\" is not a kernel; known: " + kernel_names());
            return;
        }
        try {
            std::vector<std::string> overrides = spec.fixed;
            overrides.push_back(key + "=" + value);
            (void)load_run_config(spec.machine, overrides);
        } catch (const InputError& e) {
            throw InputError(file, field, e.field() == key ? e.reason() : e.what());
        }
    };
    // The size first: checking a value loads a machine, and a grid past the cap is refused before that.
    std::size_t grid = spec.axes.empty() ? 0 : 1;
    for (const SweepAxis& axis : spec.axes) {
        const std::string field = "vary." + axis.key;
        if (!keys.insert(axis.key).second) throw InputError(file, field, "is set or varied twice");
        if (axis.values.empty()) throw InputError(file, field, "needs at least one value");
        grid = std::min(grid * std::min(axis.values.size(), kMaxSweepPoints + 1), kMaxSweepPoints + 1);
    }
    const std::size_t total = std::min(grid + spec.points.size(), kMaxSweepPoints + 1) * spec.scenarios.size();
    if (total > kMaxSweepPoints)
        throw InputError(file, "vary", fmt::format("makes more than {} points; split the sweep", kMaxSweepPoints));
    for (const SweepAxis& axis : spec.axes) {
        const std::string field = "vary." + axis.key;
        std::set<std::string> seen;
        for (std::size_t i = 0; i < axis.values.size(); ++i) {
            if (!seen.insert(axis.values[i]).second)
                throw InputError(file, fmt::format("{}[{}]", field, i), "repeats an earlier value");
            check_value(axis.key, axis.values[i], fmt::format("{}[{}]", field, i));
        }
    }
    for (std::size_t p = 0; p < spec.points.size(); ++p) {
        std::set<std::string> in_point;
        for (const auto& [key, value] : spec.points[p]) {
            const std::string field = fmt::format("points[{}].{}", p, key);
            if (!in_point.insert(key).second) throw InputError(file, field, "is given twice in one point");
            check_value(key, value, field);
        }
    }
    if (total == 0) throw InputError(file, "vary", "gives no point: vary a parameter or list [[points]]");
    if (!spec.plot_x.empty() &&
        std::none_of(spec.axes.begin(), spec.axes.end(), [&](const SweepAxis& a) { return a.key == spec.plot_x; }))
        throw InputError(file, "sweep.plot_x", "\"" + spec.plot_x + "\" is not one of the varied parameters");
}

}  // namespace pp5
