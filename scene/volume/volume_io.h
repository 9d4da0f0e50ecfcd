#pragma once
// Reading volumes from files: NIfTI-1 (.nii, .nii.gz), UNC .den (.den, .den.gz), headerless raw, and
// InVesalius projects (.inv3, declared in inv3_io.h).
//
// Every failure throws InputError naming the file, the field at fault ("header.dim[1]",
// "header.magic", "voxel data", ...) and why, so the CLI can print one line and stop. Samples that
// are NaN or infinite are rejected: a transfer function cannot classify them.

#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>

namespace pp5 {

// NIfTI-1 single file, gzipped or not, little- or big-endian. 3D scalar volumes only (dim[0] = 3,
// or more with every extra dimension 1). scl_slope/scl_inter are applied when they change values;
// the source type stays the stored one. Spacing comes from pixdim[1..3] in mm (0 reads as 1).
Volume load_nifti(const std::filesystem::path& file);

// A file of samples with no header of its own: the caller says what it holds.
struct RawLayout {
    glm::ivec3 dims{0};
    ScalarType type = ScalarType::UInt8;
    bool big_endian = false;
    std::size_t header_bytes = 0;  // skipped before the samples
    glm::vec3 spacing{1.0f};
};
// The file must hold exactly header_bytes + dims * type size bytes: a size mismatch means the layout
// is wrong, and reading on would give a sheared, garbled volume.
Volume load_raw(const std::filesystem::path& file, const RawLayout& layout);

// The UNC density format of VolPack's examples (brainsmall.den): a 62-byte header of 16-bit fields
// in the writer's byte order, then uint8 samples. Gzipped files are read too. Spacing is 1.
Volume load_den(const std::filesystem::path& file);

// By file name: .nii, .nii.gz, .den, .den.gz, .inv3. Anything else throws InputError saying which are known
// (raw files need dims and type, so they go through load_raw).
Volume load_volume(const std::filesystem::path& file);

}  // namespace pp5
