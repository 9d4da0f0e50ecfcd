#include "sim/core/config.h"

#include "sim/core/input_error.h"
#include "sim/core/named_file.h"
#include "sim/core/spelling.h"
#include "sim/core/toml_file.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <stdexcept>

namespace pp5 {
namespace {

// A --set value is text; read it as the type its parameter declares.
std::optional<ParamValue> parse_as(const ParamSpec& spec, const std::string& text) {
    switch (spec.type) {
        case ParamType::Integer: {
            std::int64_t v = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
            if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
            return v;
        }
        case ParamType::Real: {
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) return std::nullopt;
            return v;
        }
        case ParamType::Boolean:
            if (text == "true" || text == "1") return true;
            if (text == "false" || text == "0") return false;
            return std::nullopt;
        case ParamType::Text: return text;
    }
    return std::nullopt;
}

std::optional<ParamValue> from_toml(const toml::node& node) {
    if (const auto* v = node.as_integer()) return static_cast<std::int64_t>(v->get());
    if (const auto* v = node.as_floating_point()) return v->get();
    if (const auto* v = node.as_boolean()) return v->get();
    if (const auto* v = node.as_string()) return v->get();
    return std::nullopt;
}

}  // namespace

MachineConfig::MachineConfig(std::vector<const ParamGroup*> groups) : groups_(std::move(groups)) {
    for (const ParamGroup* group : groups_)
        for (const ParamSpec& spec : group->specs())
            entries_.emplace(group->prefix() + "." + spec.name, Entry{&spec, spec.default_value, "default"});
}

const ParamSpec* MachineConfig::find_spec(std::string_view key) const {
    const auto it = entries_.find(std::string(key));
    return it == entries_.end() ? nullptr : it->second.spec;
}

std::string MachineConfig::closest_key(std::string_view key) const {
    std::vector<std::string> keys;
    for (const auto& [name, entry] : entries_) keys.push_back(name);
    return closest_name(key, keys);
}

void MachineConfig::set(const std::string& key, const ParamValue& value, const std::string& origin) {
    const auto it = entries_.find(key);
    if (it == entries_.end()) {
        const std::string hint = closest_key(key);
        throw InputError(origin, key,
                         "unknown parameter" + (hint.empty() ? std::string{} : "; did you mean " + hint + "?") +
                             " (`pp5sim params` lists them all)");
    }
    const ParamSpec& spec = *it->second.spec;
    if (const std::string why = spec.check(value); !why.empty()) throw InputError(origin, key, why);
    // A real parameter given as an integer literal ("clock_mhz = 40") is stored as a real.
    if (spec.type == ParamType::Real && std::holds_alternative<std::int64_t>(value))
        it->second.value = static_cast<double>(std::get<std::int64_t>(value));
    else it->second.value = value;
    it->second.origin = origin;
}

void MachineConfig::apply_override(std::string_view assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string_view::npos || eq == 0)
        throw InputError("--set", std::string(assignment), "expected key=value, e.g. gp.count=64");
    const std::string key(assignment.substr(0, eq));
    const std::string text(assignment.substr(eq + 1));
    const ParamSpec* spec = find_spec(key);
    if (!spec) {
        set(key, text, "--set");  // reports the unknown key with a suggestion
        return;
    }
    const auto value = parse_as(*spec, text);
    if (!value) throw InputError("--set", key, "\"" + text + "\" is not a valid " + to_string(spec->type));
    set(key, *value, "--set");
}

void MachineConfig::load_file(const std::filesystem::path& path) {
    const std::string file = path.string();
    const toml::table root = read_toml_file(file);
    for (const auto& [group_key, node] : root) {
        const std::string group_name(group_key.str());
        const toml::table* table = node.as_table();
        if (!table) throw InputError(file, group_name, "expected a table such as [" + group_name + "]");
        if (group_name == "machine") {
            for (const auto& [k, v] : *table) {
                const std::string key(k.str());
                const auto* s = v.as_string();
                if ((key != "name" && key != "description" && key != "kind") || !s)
                    throw InputError(file, "machine." + key,
                                     "the [machine] table holds only name, description and kind strings");
                if (key == "kind") {
                    if (s->get() != "multicomputer" && s->get() != "uniprocessor")
                        throw InputError(
                            file, "machine.kind",
                            "must be \"multicomputer\" (Pixel-planes 5) or \"uniprocessor\", not \"" + s->get() + "\"");
                    machine_kind_ = s->get() == "uniprocessor" ? MachineKind::Uniprocessor : MachineKind::Multicomputer;
                    continue;
                }
                (key == "name" ? machine_name_ : machine_description_) = s->get();
            }
            continue;
        }
        // Nested tables ("[ring.channel]") flatten to dotted keys.
        std::vector<std::pair<std::string, const toml::table*>> pending{{group_name, table}};
        while (!pending.empty()) {
            const auto [prefix, current] = pending.back();
            pending.pop_back();
            for (const auto& [k, v] : *current) {
                const std::string key = prefix + "." + std::string(k.str());
                if (const auto* sub = v.as_table()) {
                    pending.emplace_back(key, sub);
                    continue;
                }
                const auto value = from_toml(v);
                if (!value) throw InputError(file, key, "expected a number, boolean or string");
                set(key, *value, file);
            }
        }
    }
}

const MachineConfig::Entry& MachineConfig::entry(const std::string& key) const {
    const auto it = entries_.find(key);
    if (it == entries_.end()) throw std::logic_error("parameter read but never declared: " + key);
    return it->second;
}

std::int64_t MachineConfig::integer(const std::string& key) const { return std::get<std::int64_t>(entry(key).value); }
double MachineConfig::real(const std::string& key) const { return std::get<double>(entry(key).value); }
bool MachineConfig::boolean(const std::string& key) const { return std::get<bool>(entry(key).value); }
const std::string& MachineConfig::text(const std::string& key) const { return std::get<std::string>(entry(key).value); }

std::vector<std::string> MachineConfig::keys_differing_from(const MachineConfig& other) const {
    std::vector<std::string> keys;
    auto mine = entries_.begin();
    auto theirs = other.entries_.begin();
    while (mine != entries_.end() && theirs != other.entries_.end()) {
        if (mine->first < theirs->first) {
            ++mine;
        } else if (theirs->first < mine->first) {
            ++theirs;
        } else {
            if (mine->second.value != theirs->second.value) keys.push_back(mine->first);
            ++mine;
            ++theirs;
        }
    }
    return keys;
}

nlohmann::json MachineConfig::to_json() const {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [key, e] : entries_) {
        nlohmann::json value;
        std::visit([&](const auto& v) { value = v; }, e.value);
        params[key] = {{"value", value}, {"unit", e.spec->unit}, {"origin", e.origin}};
    }
    return {{"machine",
             {{"name", machine_name_}, {"description", machine_description_}, {"kind", to_string(machine_kind_)}}},
            {"parameters", params}};
}

const std::string& MachineConfig::origin(const std::string& key) const { return entry(key).origin; }

std::string MachineConfig::describe_origin(const std::string& key) const {
    const std::string& from = origin(key);
    return from == "default" ? fmt::format("the built-in defaults (a machine file or --set changes {})", key) : from;
}

InputError MachineConfig::naming_origin(const InputError& error) const {
    if (!error.file().empty() || !entries_.count(error.field())) return error;
    return InputError(describe_origin(error.field()), error.field(), error.reason());
}

std::string to_string(MachineKind kind) { return kind == MachineKind::Uniprocessor ? "uniprocessor" : "multicomputer"; }

std::filesystem::path resolve_machine_file(const std::string& name_or_path) {
#ifdef PP5_MACHINES_DIR
    const char* builtin = PP5_MACHINES_DIR;
#else
    const char* builtin = nullptr;
#endif
    return resolve_named_file(name_or_path, {"PP5SIM_MACHINES", builtin, "--machine", "presets: sim/machines/*.toml"});
}

}  // namespace pp5
