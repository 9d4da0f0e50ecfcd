#include "frontends/staged_output.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace pp5 {

namespace fs = std::filesystem;

void StagedOutput::claim(const std::string& name) const {
    for (const Entry& e : entries_)
        if (e.name == name) throw std::logic_error("staged output: " + name + " staged twice");
}

void StagedOutput::add_image(std::string name, Image image, ImageFormat format) {
    claim(name);
    entries_.push_back(Entry{std::move(name), {}, std::move(image), format, true});
}

void StagedOutput::add_text(std::string name, std::string text) {
    claim(name);
    entries_.push_back(Entry{std::move(name), std::move(text), {}, ImageFormat::Png, false});
}

std::vector<fs::path> StagedOutput::commit() {
    fs::create_directories(directory_);
    std::vector<fs::path> partials;
    const auto clean_up = [&] {
        std::error_code ignored;
        for (const auto& p : partials) fs::remove(p, ignored);
    };
    try {
        for (const Entry& e : entries_) {
            // The partial keeps the real extension last, so OpenImageIO picks the right format. A name
            // may hold a subdirectory ("images/a.png").
            const fs::path target = directory_ / e.name;
            fs::create_directories(target.parent_path());
            const fs::path partial = target.parent_path() / (".partial-" + target.filename().string());
            partials.push_back(partial);
            if (e.is_image) {
                write_image(e.image, partial, e.format);
            } else {
                std::ofstream out(partial, std::ios::binary);
                out << e.text;
                out.close();
                if (!out) throw std::runtime_error("cannot write " + partial.string());
            }
        }
    } catch (...) {
        clean_up();
        throw;
    }
    std::vector<fs::path> written;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        const fs::path target = directory_ / entries_[i].name;
        fs::rename(partials[i], target);
        written.push_back(target);
    }
    return written;
}

}  // namespace pp5
