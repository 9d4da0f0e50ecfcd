// Choosing a loader by file name. Raw files have no recognisable name or header, so they are never
// guessed at: a wrong guess would load a plausible-looking but garbled volume.

#include "scene/volume/volume_io.h"

#include "scene/volume/inv3_io.h"
#include "scene/volume/load_checks.h"
#include "sim/core/input_error.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace pp5 {

namespace {

bool ends_with(const std::string& text, std::string_view suffix) {
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Volume load_volume(const std::filesystem::path& path) {
    std::string name = path.filename().string();
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    // A missing file is the likelier mistake than a wrong extension; say so first.
    volume_detail::require_regular_file(path);
    if (ends_with(name, ".nii") || ends_with(name, ".nii.gz")) return load_nifti(path);
    if (ends_with(name, ".den") || ends_with(name, ".den.gz")) return load_den(path);
    if (ends_with(name, ".inv3")) return load_inv3(path);

    std::string reason = "unknown volume file type";
    if (ends_with(name, ".hdr") || ends_with(name, ".img"))
        reason += " (a NIfTI/Analyze .hdr/.img pair: convert it to a single .nii file)";
    reason +=
        ": known are .nii and .nii.gz (NIfTI-1), .den and .den.gz (UNC) and .inv3 (InVesalius); a raw file "
        "needs its dims and scalar type given (volume-info --dims X Y Z --type T, or a [dataset.raw] table in a "
        "scenario)";
    throw InputError(path.string(), "file name", reason);
}

}  // namespace pp5
