#include "calibration/targets.h"

#include "calibration/timing_model.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/config.h"
#include "sim/core/input_error.h"
#include "sim/core/named_file.h"

#include <fmt/format.h>
#include "sim/core/toml_file.h"
#include "sim/core/toml_table.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace pp5 {

namespace {

// Reads one string field of a target, naming it in errors.
std::string text_field(const toml::table& row, const std::string& file, const std::string& prefix, const char* key,
                       bool required) {
    const toml::node* node = row.get(key);
    if (!node) {
        if (required) throw InputError(file, prefix + key, "is missing");
        return {};
    }
    const auto* s = node->as_string();
    if (!s) throw InputError(file, prefix + key, "must be a string");
    return s->get();
}

// Calls read(row, prefix) for each table of the optional array `name` ("figures[2]." its prefix), after
// refusing a key outside `known`.
template <typename Read>
void for_each_row(const toml::table& root, const std::string& file, const char* name,
                  std::initializer_list<std::string_view> known, Read read) {
    const toml::array* rows = root[name].as_array();
    if (rows == nullptr) return;
    for (std::size_t i = 0; i < rows->size(); ++i) {
        const std::string row_name = fmt::format("{}[{}]", name, i);
        const toml::table* row = (*rows)[i].as_table();
        if (!row) throw InputError(file, row_name, "must be a table");
        TomlTable strict(row, row_name, file);
        strict.allow(known);
        strict.finish();
        read(*row, row_name + ".");
    }
}

// The scenario a row names, or an InputError on the row's scenario field saying why it does not load.
Scenario scenario_named(const std::string& name, const std::string& file, const std::string& prefix) {
    try {
        return load_scenario(resolve_scenario_file(name));
    } catch (const InputError& e) {
        throw InputError(file, prefix + "scenario", std::string("\"") + name + "\": " + e.what());
    }
}

// [[figures]]: name, scenario, frame, picture ("final" or "first").
void read_figures(const toml::table& root, const std::string& file, TargetSet& set) {
    for_each_row(root, file, "figures", {"name", "scenario", "frame", "picture"},
                 [&](const toml::table& row, const std::string& prefix) {
                     Figure f;
                     f.name = text_field(row, file, prefix, "name", true);
                     if (f.name.empty() || f.name.find_first_of("/\\.") != std::string::npos)
                         throw InputError(file, prefix + "name", "must be a plain file name without slashes or dots");
                     f.scenario = text_field(row, file, prefix, "scenario", true);
                     if (const toml::node* frame = row.get("frame")) {
                         const auto index = frame->value<std::int64_t>();
                         if (!index || *index < 0)
                             throw InputError(file, prefix + "frame", "must be a frame index from 0");
                         f.frame = static_cast<int>(*index);
                     }
                     const std::string picture = text_field(row, file, prefix, "picture", false);
                     if (!picture.empty() && picture != "final" && picture != "first")
                         throw InputError(file, prefix + "picture",
                                          "must be final (the finished frame) or first (its first stage)");
                     f.final = picture != "first";
                     // Any scenario with that frame: a figure of a scenario no row times is recorded for the picture
                     // alone.
                     const Scenario scenario = scenario_named(f.scenario, file, prefix);
                     if (f.frame >= static_cast<int>(scenario.frames.size()))
                         throw InputError(
                             file, prefix + "frame",
                             fmt::format("must be a frame of \"{}\": 0 to {}", f.scenario, scenario.frames.size() - 1));
                     set.figures.push_back(f);
                 });
}

// [[workload]]: parameter, bounds, ratio_of (two measured rows on one machine) and why.
void read_workload(const toml::table& root, const std::string& file, TargetSet& set) {
    const MachineConfig declared(run_param_groups());  // every machine and kernel parameter, to look keys up in
    for_each_row(
        root, file, "workload", {"parameter", "bounds", "ratio_of", "why"},
        [&](const toml::table& row, const std::string& prefix) {
            WorkloadSpec w;
            w.key = text_field(row, file, prefix, "parameter", true);
            w.why = text_field(row, file, prefix, "why", true);
            const ParamSpec* spec = declared.find_spec(w.key);
            if (spec == nullptr)
                throw InputError(file, prefix + "parameter",
                                 "\"" + w.key + "\" is not a machine or kernel parameter (see `pp5sim params`)");
            if (is_timing_parameter(w.key))
                throw InputError(
                    file, prefix + "parameter",
                    "\"" + w.key +
                        "\" only changes timing: the fit's scales cover timing, the workload step what is computed");
            if (spec->type != ParamType::Integer && spec->type != ParamType::Real)
                throw InputError(file, prefix + "parameter",
                                 "\"" + w.key + "\" is not a number, so it cannot be searched for");
            w.integer = spec->type == ParamType::Integer;
            for (const auto& other : set.workload)
                if (other.key == w.key)
                    throw InputError(file, prefix + "parameter",
                                     "\"" + w.key + "\" is identified by an earlier [[workload]]");

            const toml::array* bounds = row.get_as<toml::array>("bounds");
            const auto lower = bounds && bounds->size() == 2 ? (*bounds)[0].value<double>() : std::nullopt;
            const auto upper = bounds && bounds->size() == 2 ? (*bounds)[1].value<double>() : std::nullopt;
            if (!lower || !upper || !std::isfinite(*lower) || !std::isfinite(*upper) || !(*lower < *upper))
                throw InputError(file, prefix + "bounds", "must be two numbers [lower, upper] with lower < upper");
            if ((spec->min && *lower < *spec->min) || (spec->max && *upper > *spec->max))
                throw InputError(file, prefix + "bounds",
                                 fmt::format("must lie inside the parameter's own range [{}, {}]",
                                             spec->min.value_or(-INFINITY), spec->max.value_or(INFINITY)));
            if (w.integer && (*lower != std::floor(*lower) || *upper != std::floor(*upper)))
                throw InputError(file, prefix + "bounds", "must be whole numbers for an integer parameter");
            w.lower = *lower;
            w.upper = *upper;

            const toml::array* ratio = row.get_as<toml::array>("ratio_of");
            if (!ratio || ratio->size() != 2 || !(*ratio)[0].is_string() || !(*ratio)[1].is_string())
                throw InputError(file, prefix + "ratio_of", "must name two targets: [numerator id, denominator id]");
            w.numerator = *(*ratio)[0].value<std::string>();
            w.denominator = *(*ratio)[1].value<std::string>();
            const Target* numerator = set.find(w.numerator);
            const Target* denominator = set.find(w.denominator);
            for (const auto& [id, t] : {std::pair{w.numerator, numerator}, std::pair{w.denominator, denominator}}) {
                if (t == nullptr) throw InputError(file, prefix + "ratio_of", "no target has the id \"" + id + "\"");
                if (t->is_formula())
                    throw InputError(file, prefix + "ratio_of",
                                     "\"" + id + "\" is a formula row: it simulates nothing");
                if (t->exactness != Exactness::Measured)
                    throw InputError(file, prefix + "ratio_of",
                                     "\"" + id + "\" is " + std::string(to_string(t->exactness)) +
                                         ": a workload parameter comes only from measured rows, never from an estimate "
                                         "the fit must test");
            }
            if (w.numerator == w.denominator)
                throw InputError(file, prefix + "ratio_of", "must name two different targets");
            if (numerator->machine != denominator->machine)
                throw InputError(file, prefix + "ratio_of",
                                 "the two targets must run on one machine, so that its speed cancels in the ratio");
            set.workload.push_back(std::move(w));
        });
}

}  // namespace

const Target* TargetSet::find(const std::string& id) const {
    for (const Target& t : targets)
        if (t.id == id) return &t;
    return nullptr;
}

std::string_view to_string(Exactness exactness) {
    switch (exactness) {
        case Exactness::Measured: return "measured";
        case Exactness::Estimate: return "estimate";
        case Exactness::OrderOfMagnitude: return "order-of-magnitude";
    }
    return "?";
}

std::string_view to_string(TargetUse use) {
    switch (use) {
        case TargetUse::Fit: return "fit";
        case TargetUse::Predict: return "held-out";
        case TargetUse::Check: return "check";
        case TargetUse::ByConstruction: return "by-construction";
        case TargetUse::Comparison: return "comparison";
    }
    return "?";
}

std::string_view describe(TargetUse use) {
    switch (use) {
        case TargetUse::Fit: return "fitted";
        case TargetUse::Predict: return "predicted";
        case TargetUse::Check: return "arithmetic check";
        case TargetUse::ByConstruction: return "matched by construction";
        case TargetUse::Comparison: return "comparison (another machine)";
    }
    return "?";
}

double relative_uncertainty(Exactness exactness) {
    switch (exactness) {
        case Exactness::Measured: return 0.10;
        case Exactness::Estimate: return 0.25;
        case Exactness::OrderOfMagnitude: return 0.70;
    }
    return 1.0;
}

std::filesystem::path resolve_targets_file(const std::string& name_or_path) {
#ifdef PP5_TARGETS_DIR
    const char* builtin = PP5_TARGETS_DIR;
#else
    const char* builtin = nullptr;
#endif
    return resolve_named_file(name_or_path, {"PP5SIM_TARGETS", builtin, "--targets", "traces/calibration/*.toml"});
}

namespace {

// reported, exactness and use: what every row has.
void read_value_fields(const toml::table& row, const std::string& file, const std::string& prefix, Target& t) {
    const toml::node* reported = row.get("reported");
    if (!reported) throw InputError(file, prefix + "reported", "is missing");
    const auto value = reported->value<double>();
    if (!value || !std::isfinite(*value) || *value <= 0.0)
        throw InputError(file, prefix + "reported", "must be a positive number");
    t.reported = *value;

    const std::string exactness = text_field(row, file, prefix, "exactness", true);
    if (exactness == "measured") t.exactness = Exactness::Measured;
    else if (exactness == "estimate") t.exactness = Exactness::Estimate;
    else if (exactness == "order-of-magnitude") t.exactness = Exactness::OrderOfMagnitude;
    else
        throw InputError(file, prefix + "exactness",
                         "must be measured, estimate or order-of-magnitude, not \"" + exactness + "\"");

    const std::string use = text_field(row, file, prefix, "use", true);
    constexpr TargetUse kUses[] = {TargetUse::Fit, TargetUse::Predict, TargetUse::Check, TargetUse::ByConstruction,
                                   TargetUse::Comparison};
    const auto* known =
        std::find_if(std::begin(kUses), std::end(kUses), [&](TargetUse u) { return to_string(u) == use; });
    if (known == std::end(kUses))
        throw InputError(file, prefix + "use",
                         "must be fit, held-out, check, by-construction or comparison, not \"" + use + "\"");
    t.use = *known;
}

// kernel, formula and inputs: a figure the kernel computes from a description; nothing to fit.
void read_formula_row(const toml::table& row, const std::string& file, const std::string& prefix, Target& t) {
    t.kernel = text_field(row, file, prefix, "kernel", true);
    t.formula = text_field(row, file, prefix, "formula", true);
    read_value_fields(row, file, prefix, t);
    if (t.use != TargetUse::Check)
        throw InputError(
            file, prefix + "use",
            "a formula row recomputes a paper's own equation: it predicts nothing and depends on no timing "
            "parameter, so its use is \"check\"");
    const Kernel* kernel = find_kernel(t.kernel);
    if (kernel == nullptr) throw InputError(file, prefix + "kernel", "unknown kernel \"" + t.kernel + "\"");
    const std::vector<KernelFormula> formulas = kernel->formulas();
    const KernelFormula* formula = nullptr;
    std::string known;
    for (const KernelFormula& f : formulas) {
        if (f.name == t.formula) formula = &f;
        known += (known.empty() ? "" : ", ") + f.name;
    }
    if (formula == nullptr)
        throw InputError(file, prefix + "formula",
                         "kernel " + t.kernel + " has no formula \"" + t.formula + "\"" +
                             (known.empty() ? " (it has none)" : "; known: " + known));
    t.unit = formula->unit;
    const toml::table* inputs = row.get_as<toml::table>("inputs");
    if (inputs == nullptr) throw InputError(file, prefix + "inputs", "must be a table of the formula's inputs");
    for (const auto& [key, node] : *inputs) {
        const std::string name(key.str());
        const auto input = std::find_if(formula->inputs.begin(), formula->inputs.end(),
                                        [&](const FormulaInput& i) { return i.name == name; });
        if (input == formula->inputs.end())
            throw InputError(file, prefix + "inputs." + name, "is not an input of " + t.formula);
        std::vector<double> values;
        const auto take = [&](const toml::node& n) {
            const auto v = n.value<double>();
            if (!v || !std::isfinite(*v))
                throw InputError(file, prefix + "inputs." + name, "must be a number or a list of numbers");
            values.push_back(*v);
        };
        if (const toml::array* list = node.as_array()) {
            if (list->empty() || list->size() > 16)
                throw InputError(file, prefix + "inputs." + name, "must list 1 to 16 numbers");
            for (const toml::node& n : *list) take(n);
        } else {
            take(node);
        }
        if (values.size() != input->count)
            throw InputError(file, prefix + "inputs." + name,
                             input->count == 1
                                 ? std::string("must be one number")
                                 : fmt::format("must list {} numbers, not {}", input->count, values.size()));
        t.inputs[name] = std::move(values);
    }
    for (const FormulaInput& input : formula->inputs)
        if (!t.inputs.count(input.name)) throw InputError(file, prefix + "inputs." + input.name, "is missing");
    try {
        (void)kernel->formula(t.formula, t.inputs);
    } catch (const std::domain_error& e) {
        throw InputError(file, prefix + "inputs", e.what());
    }
}

// A frame of the row's scenario, by its index.
int scenario_frame(const toml::node& node, const Scenario& scenario, const std::string& file, const std::string& field,
                   const std::string& scenario_name) {
    const auto index = node.value<std::int64_t>();
    if (!index || *index < 0 || *index >= static_cast<std::int64_t>(scenario.frames.size()))
        throw InputError(file, field,
                         fmt::format("must be a frame of \"{}\": 0 to {}", scenario_name, scenario.frames.size() - 1));
    return static_cast<int>(*index);
}

// scenario, frame, machine and metric: a figure the simulator measures on a scenario's frame. The
// scenario and machine must exist, the frame be one of the scenario's and the metric one its kernel
// measures.
void read_simulated_row(const toml::table& row, const std::string& file, const std::string& prefix, Target& t) {
    t.assumes = text_field(row, file, prefix, "assumes", false);
    t.scenario = text_field(row, file, prefix, "scenario", true);
    t.machine = text_field(row, file, prefix, "machine", true);
    t.metric = text_field(row, file, prefix, "metric", true);
    read_value_fields(row, file, prefix, t);
    if (t.use == TargetUse::Check)
        throw InputError(
            file, prefix + "use",
            "\"check\" is for formula rows (a paper's equation recomputed); a simulated row is fit, held-out, "
            "by-construction or comparison");

    const Scenario scenario = scenario_named(t.scenario, file, prefix);
    const Kernel* kernel = find_kernel(scenario.kernel);
    if (kernel == nullptr)
        throw InputError(file, prefix + "scenario",
                         "\"" + t.scenario + "\" names an unknown kernel \"" + scenario.kernel + "\"");
    std::string metrics;
    for (const KernelMetric& m : kernel->metrics()) {
        if (m.name == t.metric) t.unit = m.unit;
        metrics += (metrics.empty() ? "" : ", ") + m.name;
    }
    if (t.unit.empty())
        throw InputError(file, prefix + "metric",
                         "unknown metric \"" + t.metric + "\" for kernel " + kernel->name() +
                             (metrics.empty() ? " (it has none)" : "; known: " + metrics));
    if (const toml::node* frame = row.get("frame"))
        t.frame = scenario_frame(*frame, scenario, file, prefix + "frame", t.scenario);
    if (const toml::node* divisor = row.get("divided_by_frame")) {
        t.divided_by_frame = scenario_frame(*divisor, scenario, file, prefix + "divided_by_frame", t.scenario);
        if (t.divided_by_frame == t.frame)
            throw InputError(file, prefix + "divided_by_frame", "must differ from frame (the ratio would be 1)");
        t.unit = "ratio";
    }
    try {
        (void)resolve_machine_file(t.machine);
    } catch (const InputError& e) {
        throw InputError(file, prefix + "machine", std::string("\"") + t.machine + "\": " + e.what());
    }
}

// One [[targets]] row. A row simulates a scenario, or (with a formula) recomputes a paper's own equation.
// Its id must be new to `ids`.
Target read_target(const toml::table& row, const std::string& file, const std::string& prefix,
                   std::set<std::string>& ids) {
    const bool formula_row = row.contains("formula");
    const std::string where = prefix.substr(0, prefix.size() - 1);
    TomlTable strict(&row, where, file, formula_row ? "" : "a formula row has kernel, formula and inputs instead");
    strict.allow({"id", "source", "quote"});
    if (formula_row) strict.allow({"kernel", "formula", "inputs"});
    else strict.allow({"scenario", "frame", "machine", "metric", "divided_by_frame", "assumes"});
    strict.allow({"reported", "exactness", "use"});
    strict.finish();
    Target t;
    t.id = text_field(row, file, prefix, "id", true);
    if (!ids.insert(t.id).second)
        throw InputError(file, prefix + "id", "\"" + t.id + "\" is used by an earlier target");
    t.source = text_field(row, file, prefix, "source", true);
    t.quote = text_field(row, file, prefix, "quote", false);
    if (formula_row) read_formula_row(row, file, prefix, t);
    else read_simulated_row(row, file, prefix, t);
    return t;
}

}  // namespace

TargetSet load_targets(const std::filesystem::path& path) {
    const std::string file = path.string();
    const toml::table root = read_toml_file(file);
    TargetSet set;
    set.file = path;
    TomlTable top(&root, "", file);
    top.allow({"targets", "workload", "figures"});  // read row by row below
    TomlTable head = top.sub("calibration");
    set.name = head.text("name").value_or("");
    if (set.name.empty()) set.name = path.stem().string();
    set.description = head.text("description").value_or("");
    head.finish();
    top.finish();
    const toml::array* rows = root["targets"].as_array();
    if (!rows || rows->empty()) throw InputError(file, "targets", "needs at least one [[targets]] row");

    std::set<std::string> ids;
    for (std::size_t i = 0; i < rows->size(); ++i) {
        const std::string prefix = fmt::format("targets[{}].", i);
        const toml::table* row = (*rows)[i].as_table();
        if (!row) throw InputError(file, prefix.substr(0, prefix.size() - 1), "must be a table");
        set.targets.push_back(read_target(*row, file, prefix, ids));
    }
    read_workload(root, file, set);
    read_figures(root, file, set);
    return set;
}

}  // namespace pp5
