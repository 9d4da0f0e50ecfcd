#include "scene/volume/datasets.h"

#include "scene/volume/volume_io.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <vector>

namespace pp5 {

std::span<const PackagedDataset> packaged_datasets() {
    // Built on first use: strings are not constexpr in C++20's library, and this avoids any static
    // initialisation order question for callers in other static initialisers.
    static const std::array<PackagedDataset, 4> datasets{{
        {"ch2", "mricron-data", "/usr/share/mricron/templates/ch2.nii.gz",
         "MR head (Colin27 average), whole head with skin, 181x217x181 uint8, 1 mm"},
        {"ch2better", "mricron-data", "/usr/share/mricron/templates/ch2better.nii.gz",
         "the same MR head, finer: 301x370x316 uint8, 0.5 mm"},
        {"brainsmall", "libvolpack1-dev", "/usr/share/doc/libvolpack1-dev/examples/brainsmall.den",
         "MR head from UNC Chapel Hill (VolPack's example), 128x128x84 uint8"},
        {"ct-head", "invesalius-examples", "/usr/share/doc/invesalius-examples/examples/Cranium.inv3",
         "CT head (InVesalius example), 256x256x108 int16 HU, 0.957x0.957x1.5 mm"},
    }};
    return datasets;
}

const PackagedDataset* find_packaged_dataset(std::string_view name) {
    const auto all = packaged_datasets();
    const auto it = std::find_if(all.begin(), all.end(), [&](const PackagedDataset& d) { return d.name == name; });
    return it == all.end() ? nullptr : &*it;
}

Volume load_packaged_dataset(std::string_view name) {
    const PackagedDataset* dataset = find_packaged_dataset(name);
    if (dataset == nullptr) {
        std::vector<std::string> known;
        for (const auto& d : packaged_datasets()) known.push_back(d.name);
        throw InputError(std::string(name), "dataset",
                         fmt::format("unknown packaged dataset (known: {})", fmt::join(known, ", ")));
    }
    std::filesystem::path path = dataset->path;
    // Debian compresses large documentation files in some releases; the loaders read gzip as well.
    if (!std::filesystem::exists(path) && std::filesystem::exists(path.string() + ".gz")) path += ".gz";
    if (!std::filesystem::exists(path)) {
        throw InputError(dataset->path, "dataset",
                         fmt::format("not installed: run `sudo apt-get install {}`", dataset->package));
    }
    Volume volume = load_volume(path);
    volume.set_name(dataset->name);
    return volume;
}

}  // namespace pp5
