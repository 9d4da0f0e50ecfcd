#pragma once
// The resolved machine configuration: every declared parameter with its value and where the value
// came from (default, a machine file, or a --set override). Written as config.json beside results.

#include "sim/core/input_error.h"
#include "sim/core/param.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pp5 {

// What the machine file describes: Pixel-planes 5 (GPs, renderers, ring), or one processor that runs
// the same algorithms one step after another (Levoy's Sun 4/280), timed from the same recorded work.
enum class MachineKind { Multicomputer, Uniprocessor };
std::string to_string(MachineKind kind);

class MachineConfig {
public:
    // Starts from every group's defaults. Groups must outlive the configuration.
    explicit MachineConfig(std::vector<const ParamGroup*> groups);

    // Reads a TOML machine file: an optional [machine] table (name, description, kind) and one table per
    // parameter group. Unknown keys, wrong types and out-of-range values throw InputError naming the
    // file and the key.
    void load_file(const std::filesystem::path& path);
    // "gp.count=64", as given to --set; the origin is "--set".
    void apply_override(std::string_view assignment);
    // Validates and stores; `origin` names where the value came from, for errors and config.json.
    void set(const std::string& key, const ParamValue& value, const std::string& origin);

    std::int64_t integer(const std::string& key) const;
    double real(const std::string& key) const;
    bool boolean(const std::string& key) const;
    const std::string& text(const std::string& key) const;
    // Where a parameter's value came from: "default", a machine file's path, or "--set".
    const std::string& origin(const std::string& key) const;
    // The same as an error names it: the machine file, "--set", or the defaults.
    std::string describe_origin(const std::string& key) const;
    // A check made after loading (a component's or a kernel's) refuses a value with reject_field, not
    // knowing which file or option gave it; this names it. Other errors come back unchanged.
    InputError naming_origin(const InputError& error) const;

    const std::string& machine_name() const { return machine_name_; }
    const std::string& machine_description() const { return machine_description_; }
    MachineKind machine_kind() const { return machine_kind_; }
    const std::vector<const ParamGroup*>& groups() const { return groups_; }
    const ParamSpec* find_spec(std::string_view key) const;

    // The parameters both configurations have whose values differ, in key order.
    std::vector<std::string> keys_differing_from(const MachineConfig& other) const;
    const ParamValue& value(const std::string& key) const { return entry(key).value; }

    nlohmann::json to_json() const;

private:
    struct Entry {
        const ParamSpec* spec;
        ParamValue value;
        std::string origin;
    };
    const Entry& entry(const std::string& key) const;
    std::string closest_key(std::string_view key) const;

    std::vector<const ParamGroup*> groups_;
    std::map<std::string, Entry> entries_;  // ordered, so config.json is stable
    std::string machine_name_ = "default";
    std::string machine_description_;
    MachineKind machine_kind_ = MachineKind::Multicomputer;
};

// Finds a machine file: an existing path as given, else a preset name ("pxpl5") looked up in the
// preset directories (sim/machines in the source tree and beside the installed binary).
std::filesystem::path resolve_machine_file(const std::string& name_or_path);

// Runs `work` (which builds or runs a machine and kernel from `config`) with its refusals naming the
// machine file, --set or the defaults that gave the refused value.
template <class Work>
decltype(auto) naming_parameter_origins(const MachineConfig& config, Work&& work) {
    try {
        return std::forward<Work>(work)();
    } catch (const InputError& error) {
        throw config.naming_origin(error);
    }
}

}  // namespace pp5
