#pragma once
// Real volumes that Debian packages install, by short name, so scenarios and benchmarks can name
// "ch2" rather than a path. The data is never copied into the project.

#include "scene/volume/volume.h"

#include <span>
#include <string>
#include <string_view>

namespace pp5 {

struct PackagedDataset {
    std::string name;         // "ch2"
    std::string package;      // the Debian package that installs it
    std::string path;         // where the package puts it
    std::string description;  // one line for listings
};

std::span<const PackagedDataset> packaged_datasets();
const PackagedDataset* find_packaged_dataset(std::string_view name);  // nullptr if unknown

// Loads by short name; the volume's name() is the short name. Throws InputError(path, "dataset",
// "not installed: run `sudo apt-get install <package>`") if the file is absent, and
// InputError(name, "dataset", ...) listing the known names if the name is unknown.
Volume load_packaged_dataset(std::string_view name);

}  // namespace pp5
