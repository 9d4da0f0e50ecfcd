#include "sim/core/toml_table.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <cmath>

namespace pp5 {

TomlTable::TomlTable(const toml::table* table, std::string path, std::string file, std::string hint)
    : table_(table), path_(std::move(path)), file_(std::move(file)), hint_(std::move(hint)) {}

std::string TomlTable::field(const std::string& key) const {
    if (key.empty()) return path_;
    return path_.empty() ? key : path_ + "." + key;
}

void TomlTable::fail(const std::string& key, const std::string& reason) const {
    throw InputError(file_, field(key), reason);
}

void TomlTable::remember(std::string_view key) {
    if (known_set_.insert(std::string(key)).second) known_.emplace_back(key);
}

const toml::node* TomlTable::node(const std::string& key) {
    remember(key);
    return table_ != nullptr ? table_->get(key) : nullptr;
}

void TomlTable::allow(std::initializer_list<std::string_view> keys) {
    for (const std::string_view key : keys) remember(key);
}

TomlTable TomlTable::sub(const std::string& key) {
    const toml::node* n = node(key);
    if (n != nullptr && !n->is_table()) fail(key, "expected a table");
    return TomlTable(n != nullptr ? n->as_table() : nullptr, field(key), file_, hint_);
}

std::optional<std::string> TomlTable::text(const std::string& key) {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (!n->is_string()) fail(key, "expected a string");
    return n->as_string()->get();
}

std::string TomlTable::required_text(const std::string& key) {
    std::optional<std::string> value = text(key);
    if (!value) fail(key, "is missing");
    return std::move(*value);
}

std::optional<std::vector<std::string>> TomlTable::text_list(const std::string& key) {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const toml::array* list = n->as_array();
    if (list == nullptr) fail(key, "expected a list of strings");
    std::vector<std::string> out;
    for (const toml::node& item : *list) {
        if (!item.is_string()) fail(key, "expected a list of strings");
        out.push_back(item.as_string()->get());
    }
    return out;
}

std::optional<double> TomlTable::number(const std::string& key, double min, double max) {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    double v = 0;
    if (const auto* i = n->as_integer()) v = static_cast<double>(i->get());
    else if (const auto* f = n->as_floating_point()) v = f->get();
    else fail(key, "expected a number");
    check_range(key, v, min, max);
    return v;
}

std::optional<std::int64_t> TomlTable::integer(const std::string& key, std::int64_t min, std::int64_t max) {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const auto* i = n->as_integer();
    if (i == nullptr) fail(key, "expected an integer");
    if (i->get() < min || i->get() > max)
        fail(key, fmt::format("{} is outside the allowed range [{}, {}]", i->get(), min, max));
    return i->get();
}

std::optional<bool> TomlTable::boolean(const std::string& key) {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (!n->is_boolean()) fail(key, "expected true or false");
    return n->as_boolean()->get();
}

std::optional<std::array<double, 3>> TomlTable::triple(const std::string& key, double min, double max) {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const auto* a = n->as_array();
    if (a == nullptr || a->size() != 3) fail(key, "expected an array of three numbers");
    std::array<double, 3> v{};
    for (std::size_t i = 0; i < 3; ++i) {
        const toml::node& e = *a->get(i);
        if (const auto* iv = e.as_integer()) v[i] = static_cast<double>(iv->get());
        else if (const auto* fv = e.as_floating_point()) v[i] = fv->get();
        else fail(key, "expected an array of three numbers");
        check_range(key, v[i], min, max);
    }
    return v;
}

const toml::array* TomlTable::table_array_node(const std::string& key) {
    const toml::node* n = node(key);
    if (n == nullptr) return nullptr;
    const auto* a = n->as_array();
    if (a == nullptr) fail(key, "expected an array of tables");
    return a;
}

TomlTable TomlTable::array_item(const std::string& key, const toml::array& rows, std::size_t i) const {
    const std::string name = fmt::format("{}[{}]", field(key), i);
    const auto* t = rows.get(i)->as_table();
    if (t == nullptr) throw InputError(file_, name, "expected a table");
    return TomlTable(t, name, file_, hint_);
}

void TomlTable::finish() const {
    if (table_ == nullptr) return;
    for (const auto& [k, v] : *table_) {
        if (known_set_.count(k.str())) continue;
        std::string listed;
        for (std::size_t i = 0; i < known_.size(); ++i)
            listed += (i == 0 ? "" : i + 1 == known_.size() ? " and " : ", ") + known_[i];
        const std::string where = path_.empty() ? "the file" : path_;
        fail(std::string(k.str()),
             fmt::format("unknown field; {} has {}{}", where, listed.empty() ? "no fields" : listed,
                         hint_.empty() ? "" : " (" + hint_ + ")"));
    }
}

void TomlTable::check_range(const std::string& key, double v, double min, double max) const {
    if (!std::isfinite(v)) fail(key, "must be a finite number");
    if (v < min || v > max) fail(key, fmt::format("{} is outside the allowed range [{}, {}]", v, min, max));
}

}  // namespace pp5
