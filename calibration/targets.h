#pragma once
// Calibration targets as data: one row per figure a paper reported, naming the scenario and frame that
// reproduces it, the machine it was reported for, the metric, the value, how exact the source is, and
// whether the fit may use it or must predict it (held out). Read from a TOML file under
// traces/calibration/ (format in traces/README.md); every field is checked, and a bad one is an
// InputError naming the file, the field and the reason.

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace pp5 {

// How exact the source is: it sets the target's weight in the fit (its relative uncertainty).
enum class Exactness {
    Measured,          // timed on a real machine ("6 seconds on a Sun 4/280"): 10%
    Estimate,          // a designer's estimate ("about 1 s", "1/20 s"): 25%
    OrderOfMagnitude,  // "several seconds": 70%
};
std::string_view to_string(Exactness exactness);
double relative_uncertainty(Exactness exactness);

// What a row is for, which decides where its error is counted: only predictions test the model on
// figures it never saw, so only they make the predicted (held-out) totals.
enum class TargetUse {
    Fit,             // "fit": the scales are chosen to match it
    Predict,         // "held-out": never fitted, predicted by the fitted model
    Check,           // "check": a paper's own equation recomputed (formula rows); tests arithmetic, not the model
    ByConstruction,  // "by-construction": an input of its scenario was chosen to match it (a view distance)
    Comparison,      // "comparison": the paper's figure for another machine, beside the simulated machine's
};
std::string_view to_string(TargetUse use);  // the file's word
std::string_view describe(TargetUse use);   // the report's: "fitted", "predicted", "arithmetic check"...

struct Target {
    std::string id;
    std::string source;         // paper and section
    std::string quote;          // the words the figure comes from, or a paraphrase
    std::string assumes;        // optional: the paper's reasoning behind the figure, shown when the row misses it
    std::string scenario;       // a scenario name or file
    int frame = 0;              // index into the scenario's frames
    std::string machine;        // preset name or machine file
    std::string metric;         // one of the scenario's kernel's metrics (Kernel::metrics)
    std::string unit;           // the metric's, or "ratio" when divided by another frame's
    int divided_by_frame = -1;  // >= 0: the metric at `frame` over its value at this frame (a ratio)
    double reported = 0.0;
    Exactness exactness = Exactness::Estimate;
    TargetUse use = TargetUse::Fit;
    bool fitted() const { return use == TargetUse::Fit; }
    // A formula row instead (no scenario, frame or machine): a kernel's figure computed from a
    // description (Kernel::formulas), always an arithmetic check.
    std::string kernel;
    std::string formula;
    std::map<std::string, std::vector<double>> inputs;
    bool is_formula() const { return !formula.empty(); }
};

// A picture `pp5sim reproduce` writes beside the table: a recorded frame of a target's scenario.
struct Figure {
    std::string name;      // images/<name>.png
    std::string scenario;  // a scenario some target names, whose frame `frame` it records
    int frame = 0;
    bool final = true;  // the finished frame, or (false) its first stage (the crude pass)
};

// A workload parameter the papers do not give (what a kernel computes, not how fast: a refinement
// threshold, a sample count), identified before any scale is fitted from the ratio of two measured rows
// on one machine, so that the machine's speed cancels. Never from a designer's estimate.
struct WorkloadSpec {
    std::string key;     // a machine parameter that changes what is computed ("levoy.refinement_threshold")
    double lower = 0.0;  // the search's bounds, inside the parameter's own range
    double upper = 0.0;
    bool integer = false;   // the parameter's type
    std::string numerator;  // target ids: simulated numerator / denominator should equal the reported ratio
    std::string denominator;
    std::string why;  // what ties the parameter to that ratio
};

struct TargetSet {
    std::filesystem::path file;
    std::string name;
    std::string description;
    std::vector<Target> targets;
    std::vector<Figure> figures;
    std::vector<WorkloadSpec> workload;  // identified in this order, each with the ones before it set

    const Target* find(const std::string& id) const;
};

// Reads and checks a target file ([calibration], [[targets]], [[workload]], [[figures]]): metrics the scenario's kernel
// does not offer, unknown exactness or use, scenarios or machines that do not resolve, frames outside the scenario,
// non-positive values and repeated ids are errors.
TargetSet load_targets(const std::filesystem::path& file);
// A path, or the name of a shipped target file (traces/calibration/NAME.toml).
std::filesystem::path resolve_targets_file(const std::string& name_or_path);
inline constexpr const char* kDefaultTargets = "levoy89";

}  // namespace pp5
