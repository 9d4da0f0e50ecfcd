#pragma once
// Reads one TOML table of a user's file strictly, for every input pp5sim takes in TOML (scenarios,
// sweeps, calibration targets): each key read, or declared as allowed, is remembered, and finish()
// refuses the rest, naming the field and listing what the table may hold, so that a misspelt key is an
// error rather than a silently ignored setting. Every refusal is an InputError naming the file and the
// field's dotted path (`image.width`, `frames[2].camera`).

#include <toml++/toml.h>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace pp5 {

class TomlTable {
public:
    // `table` may be null (an absent table: every read finds nothing). `path` is the table's dotted
    // path ("" for the file's root); `hint` ends every unknown-field refusal (where the format is
    // documented, say).
    TomlTable(const toml::table* table, std::string path, std::string file, std::string hint = {});

    bool has(const std::string& key) const { return table_ != nullptr && table_->contains(key); }
    // The dotted path of `key` in this table ("" names the table itself).
    std::string field(const std::string& key) const;
    [[noreturn]] void fail(const std::string& key, const std::string& reason) const;
    const std::string& file() const { return file_; }

    // The node at `key`, remembered as read; null when absent.
    const toml::node* node(const std::string& key);
    // Keys the table may hold that the caller reads from node() later, or not at all.
    void allow(std::initializer_list<std::string_view> keys);

    // A sub-table, read strictly by the caller (absent: a reader over nothing).
    TomlTable sub(const std::string& key);
    std::optional<std::string> text(const std::string& key);
    // The text at `key`, refused when absent.
    std::string required_text(const std::string& key);
    std::optional<std::vector<std::string>> text_list(const std::string& key);
    std::optional<double> number(const std::string& key, double min, double max);
    std::optional<std::int64_t> integer(const std::string& key, std::int64_t min, std::int64_t max);
    std::optional<bool> boolean(const std::string& key);
    std::optional<std::array<double, 3>> triple(const std::string& key, double min, double max);

    // An array of tables, each read strictly by `each(TomlTable&)` and finished; false when absent.
    template <class Each>
    bool table_array(const std::string& key, Each each) {
        const toml::array* rows = table_array_node(key);
        if (rows == nullptr) return false;
        for (std::size_t i = 0; i < rows->size(); ++i) {
            TomlTable row = array_item(key, *rows, i);
            each(row);
            row.finish();
        }
        return true;
    }

    // Refuses the first key neither read nor allowed: "unknown field; <table> has a, b and c".
    void finish() const;

private:
    void remember(std::string_view key);
    void check_range(const std::string& key, double v, double min, double max) const;
    const toml::array* table_array_node(const std::string& key);
    TomlTable array_item(const std::string& key, const toml::array& rows, std::size_t i) const;

    const toml::table* table_;
    std::string path_;
    std::string file_;
    std::string hint_;
    std::vector<std::string> known_;  // in the order first read or allowed, for the refusal
    std::set<std::string, std::less<>> known_set_;
};

}  // namespace pp5
