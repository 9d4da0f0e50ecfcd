#pragma once
// InVesalius 3 project files (.inv3): a gzipped tar holding main.plist, an XML property list that
// describes the volume (its matrix file, dtype, shape and spacing), and that matrix as headerless
// little-endian samples. Debian's invesalius-examples ships a CT head in this form (Cranium.inv3).

#include "kernels/volume/volume.h"

#include <filesystem>

namespace pp5 {

// Throws InputError(file, field, reason) for a corrupt archive ("archive"), a missing member
// ("main.plist", "matrix.dat"), a plist without a needed key ("main.plist: matrix.shape", ...), an
// unsupported dtype, or a matrix whose size does not match its shape and dtype.
Volume load_inv3(const std::filesystem::path& file);

}  // namespace pp5
