#pragma once
// Parameters, declared once next to the component that uses them (as SST's component tables and
// gem5's Param declarations do): type, unit, default, allowed range, a one-line doc and provenance.
// The machine file, `--set` overrides, `pp5sim params` and config.json are all driven by these tables.

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace pp5 {

enum class ParamType { Integer, Real, Boolean, Text };

using ParamValue = std::variant<std::int64_t, double, bool, std::string>;

std::string to_string(ParamType type);
std::string format_param_value(const ParamValue& value);

// Where a default comes from, so a user can tell a published number from a guess.
enum class Provenance { Paper, Hardware, Default };
std::string to_string(Provenance provenance);

// Where a documented guess could plausibly lie, and why: the range the uncertainty of a simulated figure
// is propagated over (calibration/uncertainty.h). Not the allowed range, which only keeps values sane.
struct PlausibleRange {
    double low = 0.0;
    double high = 0.0;
    std::string why;
    bool per_operation = false;  // a cost charged per operation: time grows with it along a straight line
};

struct ParamSpec {
    std::string name;  // local to its group: "clock_mhz"
    ParamType type = ParamType::Integer;
    std::string unit;  // "MHz", "bits", "count", "" for none
    ParamValue default_value;
    std::optional<double> min;  // inclusive bounds for numbers
    std::optional<double> max;
    std::vector<std::string> choices;  // allowed values of a Text parameter; empty = any
    std::string doc;
    Provenance provenance = Provenance::Default;
    std::string source;                       // e.g. "Levoy 1989, Implementation on Pixel-planes 5"
    std::optional<PlausibleRange> plausible;  // numbers only; every timing guess has one (tests/unit/sim)
    // It changes when the machine's work happens, never what is computed: a frame recorded on one
    // machine may be re-timed on another that differs only in such parameters (calibration, sweeps, the
    // browser tool's machine controls).
    bool timing_only = false;

    // Empty when `value` is acceptable, else the reason it is not.
    std::string check(const ParamValue& value) const;
};

// All parameters of one kind of component ("gp", "renderer", "ring.channel"). Keys are "group.name".
class ParamGroup {
public:
    ParamGroup(std::string prefix, std::string description);

    ParamGroup& integer(std::string name, std::int64_t def, std::string unit, double min, double max, std::string doc,
                        Provenance provenance, std::string source);
    ParamGroup& real(std::string name, double def, std::string unit, double min, double max, std::string doc,
                     Provenance provenance, std::string source);
    ParamGroup& boolean(std::string name, bool def, std::string doc, Provenance provenance, std::string source);
    ParamGroup& text(std::string name, std::string def, std::vector<std::string> choices, std::string doc,
                     Provenance provenance, std::string source);
    // The plausible range of the parameter declared last; it must hold the default and lie in the
    // allowed range.
    ParamGroup& plausible(double low, double high, std::string why);
    // The same range as factors of the default (a hand count that could be half or twice, say).
    ParamGroup& plausible_factor(double low_factor, double high_factor, std::string why);
    // An operation's cost counted by hand from its arithmetic: half to twice the count.
    ParamGroup& hand_counted();
    // A cost so counted, declared in one call: flops at a processor's rate (0 to 1e6) or cycles at its
    // clock (0 to 1e7), `count` saying how the default was counted.
    ParamGroup& hand_counted_flops(std::string name, double def, std::string doc, std::string count);
    ParamGroup& hand_counted_cycles(std::string name, double def, std::string doc, std::string count);
    // The parameter declared last only changes timing (ParamSpec::timing_only).
    ParamGroup& timing_only();
    // Every parameter of the group, declared before or after, only changes timing.
    ParamGroup& all_timing_only();

    const std::string& prefix() const { return prefix_; }
    const std::string& description() const { return description_; }
    const std::vector<ParamSpec>& specs() const { return specs_; }

private:
    ParamGroup& add(ParamSpec spec);

    std::string prefix_;
    std::string description_;
    std::vector<ParamSpec> specs_;
    bool all_timing_only_ = false;
};

}  // namespace pp5
