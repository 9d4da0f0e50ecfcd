#pragma once
// Results appear whole or not at all: files are staged in memory while a run works, and only when
// everything has succeeded are they written under temporary names and renamed into place.

#include "frontends/image_io.h"

#include <filesystem>
#include <string>
#include <vector>

namespace pp5 {

class StagedOutput {
public:
    explicit StagedOutput(std::filesystem::path directory) : directory_(std::move(directory)) {}

    void add_image(std::string name, Image image, ImageFormat format);
    void add_text(std::string name, std::string text);

    // Writes every staged file; on any failure removes what it wrote and throws.
    // Returns the paths written, in the order staged.
    std::vector<std::filesystem::path> commit();

    const std::filesystem::path& directory() const { return directory_; }

private:
    struct Entry {
        std::string name;
        std::string text;
        Image image;
        ImageFormat format = ImageFormat::Png;
        bool is_image = false;
    };
    void claim(const std::string& name) const;  // a name may be staged once

    std::filesystem::path directory_;
    std::vector<Entry> entries_;
};

}  // namespace pp5
