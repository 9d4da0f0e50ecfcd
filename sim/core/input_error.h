#pragma once
// The one error type for bad user input: a machine file, a scenario, a volume, a command-line value.
// It always names where the problem is (file), what is wrong (field) and why (reason), so that the
// CLI can print one clear line and exit non-zero without writing any output.

#include <stdexcept>
#include <string>

namespace pp5 {

class InputError : public std::runtime_error {
public:
    InputError(std::string file, std::string field, std::string reason)
        : std::runtime_error(compose(file, field, reason)),
          file_(std::move(file)),
          field_(std::move(field)),
          reason_(std::move(reason)) {}

    const std::string& file() const { return file_; }
    const std::string& field() const { return field_; }
    const std::string& reason() const { return reason_; }

private:
    static std::string compose(const std::string& file, const std::string& field, const std::string& reason) {
        std::string text = file.empty() ? std::string("<input>") : file;
        if (!field.empty() && field != file) text += ": " + field;  // a command-line option is both
        return text + ": " + reason;
    }

    std::string file_;
    std::string field_;
    std::string reason_;
};

// Refuses a value whose file is not known where it is checked (a setting validated on its own); the
// reader that knows the file catches the error and names it.
[[noreturn]] inline void reject_field(const std::string& field, const std::string& reason) {
    throw InputError("", field, reason);
}

}  // namespace pp5
