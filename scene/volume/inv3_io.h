#pragma once
// InVesalius 3 project files (.inv3): a gzipped tar holding main.plist, an XML property list that
// describes the volume (its matrix file, dtype, shape and spacing), and that matrix as headerless
// little-endian samples. Debian's invesalius-examples ships a CT head in this form (Cranium.inv3).

#include "scene/volume/volume.h"

#include <filesystem>

namespace pp5 {

// The volume of an InVesalius project, slices in stored order (for Cranium.inv3 that puts superior at
// +z, as in the NIfTI heads). Masks, surfaces and measurements in the project are passed over.
//
// Throws InputError(file, field, reason) with field
//   "archive"                     not a gzipped tar, a bad tar header, or data cut short;
//   "main.plist", "matrix.dat"    the member is missing (the matrix by the name main.plist gives it),
//                                 or the matrix size does not match its shape and dtype;
//   "main.plist: matrix.dtype"    (and .filename, .shape[i], spacing[i]) a key missing or malformed,
//                                 or a dtype that a Volume cannot hold.
Volume load_inv3(const std::filesystem::path& file);

}  // namespace pp5
