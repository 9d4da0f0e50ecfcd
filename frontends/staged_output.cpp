#include "frontends/staged_output.h"

#include "sim/core/input_error.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

namespace pp5 {

namespace fs = std::filesystem;

namespace {

constexpr const char* kManifest = ".pp5sim-outputs";
constexpr const char* kPartial = ".partial-";
constexpr const char* kPrevious = ".previous-";

[[noreturn]] void cannot_write(const fs::path& path, const std::string& why) {
    throw InputError(path.string(), "output", why);
}

fs::path beside(const fs::path& target, const char* prefix) {
    return target.parent_path() / (prefix + target.filename().string());
}

}  // namespace

void check_output_folder(const fs::path& directory, const std::string& option) {
    if (directory.empty()) throw InputError(option, option, "is empty: name a folder");
    std::error_code error;
    // The folder itself if it exists, else its nearest existing ancestor, which must be a folder.
    fs::path at = directory;
    while (!at.empty() && !fs::exists(fs::symlink_status(at, error))) {
        if (!at.has_parent_path() || at.parent_path() == at) {
            at = ".";
            break;
        }
        at = at.parent_path();
    }
    if (at.empty()) at = ".";
    const fs::file_status status = fs::status(at, error);
    if (error) throw InputError(at.string(), option, "cannot be used as an output folder: " + error.message());
    if (!fs::is_directory(status))
        throw InputError(at.string(), option,
                         at == directory
                             ? "exists and is not a folder"
                             : "is a file, so the output folder " + directory.string() + " cannot be made under it");
    if (::access(at.c_str(), W_OK | X_OK) != 0)
        throw InputError(at.string(), option, std::string("cannot be written: ") + std::strerror(errno));
}

void check_output_file(const fs::path& file, const std::string& option) {
    std::error_code error;
    if (file.empty() || !file.has_filename()) throw InputError(file.string(), option, "needs a file name");
    if (fs::is_directory(file, error)) throw InputError(file.string(), option, "is a folder, not a file to write");
    check_output_folder(file.has_parent_path() ? file.parent_path() : fs::path("."), option);
}

StagedOutput::StagedOutput(fs::path directory, std::string option)
    : directory_(std::move(directory)), option_(std::move(option)) {
    check_output_folder(directory_, option_);
}

void StagedOutput::claim(const fs::path& target) const {
    for (const Entry& e : entries_)
        if (e.target == target) throw std::logic_error("staged output: " + target.string() + " staged twice");
}

StagedOutput::~StagedOutput() {
    if (!committed_) remove_temporaries();
}

void StagedOutput::remove_temporaries() {
    std::error_code ignored;
    for (const fs::path& p : temporaries_) fs::remove(p, ignored);
    temporaries_.clear();
    // Only folders this run made, and only while empty: nothing of anyone else's goes.
    for (auto it = made_folders_.rbegin(); it != made_folders_.rend(); ++it) fs::remove(*it, ignored);
    made_folders_.clear();
}

// Makes the folders a file at `target` needs, remembering which did not exist before.
void StagedOutput::make_folder_for(const fs::path& target) {
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code error;
    std::vector<fs::path> missing;
    for (fs::path p = folder; !p.empty() && !fs::exists(p, error); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    fs::create_directories(folder, error);
    if (error) cannot_write(folder, "cannot make the folder: " + error.message());
    made_folders_.insert(made_folders_.end(), missing.rbegin(), missing.rend());
}

void StagedOutput::add_image(std::string name, const Image& image, ImageFormat format) {
    const fs::path target = directory_ / name;
    claim(target);
    make_folder_for(target);
    // The partial keeps the real extension last, so OpenImageIO picks the right format.
    const fs::path partial = beside(target, kPartial);
    temporaries_.push_back(partial);
    try {
        write_image(image, partial, format);
    } catch (const std::exception& ex) {
        cannot_write(target, ex.what());
    }
    entries_.push_back(Entry{target, {}, true, true});
}

void StagedOutput::add_text(std::string name, std::string text) {
    const fs::path target = directory_ / name;
    claim(target);
    entries_.push_back(Entry{target, std::move(text), false, true});
}

void StagedOutput::add_text_at(const fs::path& file, std::string text, const std::string& option) {
    check_output_file(file, option);
    claim(file);
    entries_.push_back(Entry{file, std::move(text), false, false});
}

std::vector<fs::path> StagedOutput::commit() {
    std::error_code error;
    // Nothing is written if a file's place is taken by a folder.
    for (const Entry& e : entries_)
        if (fs::is_directory(e.target, error))
            throw InputError(e.target.string(), option_, "is a folder where pp5sim would write a file");
    std::vector<fs::path> partials, replaced, placed;
    const auto undo = [&] {
        std::error_code ignored;
        for (const fs::path& p : partials) fs::remove(p, ignored);
        for (const fs::path& t : placed) fs::remove(t, ignored);
        for (const fs::path& t : replaced) fs::rename(beside(t, kPrevious), t, ignored);
    };
    try {
        for (const Entry& e : entries_) {
            // A name may hold a subdirectory ("images/a.png").
            const fs::path partial = beside(e.target, kPartial);
            partials.push_back(partial);
            if (!e.written) {
                make_folder_for(e.target);
                errno = 0;
                std::ofstream out(partial, std::ios::binary);
                out << e.text;
                out.close();
                if (!out) cannot_write(e.target, errno != 0 ? std::strerror(errno) : "the write failed");
            }
        }
        // Every file is written: put them in place, keeping what they replace until all are.
        for (std::size_t i = 0; i < entries_.size(); ++i) {
            const fs::path& target = entries_[i].target;
            if (fs::exists(target, error)) {
                fs::rename(target, beside(target, kPrevious), error);
                if (error) cannot_write(target, "cannot be replaced: " + error.message());
                replaced.push_back(target);
            }
            fs::rename(partials[i], target, error);
            if (error) cannot_write(target, error.message());
            placed.push_back(target);
        }
    } catch (...) {
        undo();
        throw;
    }
    committed_ = true;
    temporaries_.clear();
    made_folders_.clear();
    std::error_code ignored;
    for (const fs::path& t : replaced) fs::remove(beside(t, kPrevious), ignored);
    if (owns_) write_manifest_and_clean();
    return placed;
}

void StagedOutput::write_manifest_and_clean() {
    std::error_code ignored;
    std::set<std::string> now;
    for (const Entry& e : entries_)
        if (e.in_folder) now.insert(e.target.lexically_relative(directory_).generic_string());
    // What the last run here wrote and this one did not: its frames beyond this run's, say.
    std::ifstream previous(directory_ / kManifest);
    for (std::string line; std::getline(previous, line);) {
        const fs::path old = fs::path(line).lexically_normal();
        if (line.empty() || now.count(line) || old.is_absolute() || old.string().starts_with("..")) continue;
        fs::remove(directory_ / old, ignored);
    }
    previous.close();
    // Temporary files of a run that was killed while committing.
    for (fs::directory_iterator it(directory_, ignored), end; !ignored && it != end; it.increment(ignored)) {
        const std::string name = it->path().filename().string();
        if (name.starts_with(kPartial) || name.starts_with(kPrevious)) fs::remove(it->path(), ignored);
    }
    std::ofstream manifest(directory_ / kManifest, std::ios::binary);
    for (const std::string& name : now) manifest << name << '\n';
}

}  // namespace pp5
