// The UNC density (.den) format, as written by denfile.c in VolPack's examples
// (/usr/share/doc/libvolpack1-dev/examples/denfile.c). The header is 62 bytes, all fields in the
// writing machine's byte order, which the version field reveals:
//
//   offset  field                 type
//        0  map_version           int16, always 1 (reads as 0x0100 when byte-swapped)
//        2  orig_min/max/len[3]   int16 x 9   the original scan's grid
//       20  extr_min/max/len[3]   int16 x 9   the part of it extracted
//       38  map_min/max/len[3]    int16 x 9   this file's grid; map_len is the volume's dims
//       56  map_warps             int16       resamplings since extraction
//       58  map_length            int32       map_len[0] * map_len[1] * map_len[2]
//       62  samples               uint8, x fastest
//
// No physical voxel size is stored, so spacing is 1, as in VolPack, which renders on the voxel grid.
// (brainsmall.den, 128x128x84 taken from a 256x256x109 scan, was warped by 2, 2 and 1.30 per axis:
// cubic voxels if the scan's slices were about 1.5 times its pixel size, as MR slices then often
// were. The header does not say.)

#include "scene/volume/volume_io.h"

#include "scene/volume/byte_fields.h"
#include "scene/volume/gz_file.h"
#include "scene/volume/load_checks.h"
#include "scene/volume/sample_decode.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <cstdint>

namespace pp5 {

namespace {

using volume_detail::read_field;

constexpr std::size_t kDenHeaderBytes = 62;
constexpr std::size_t kMapLenOffset = 50;
constexpr std::size_t kMapLengthOffset = 58;

std::endian byte_order(std::span<const std::byte> header, const std::string& file) {
    if (read_field<std::int16_t>(header, 0, std::endian::little) == 1) return std::endian::little;
    if (read_field<std::int16_t>(header, 0, std::endian::big) == 1) return std::endian::big;
    throw InputError(file, "header.map_version",
                     fmt::format("is {:#06x}: a .den file starts with version 1 (is this a .den file?)",
                                 read_field<std::uint16_t>(header, 0, std::endian::little)));
}

}  // namespace

Volume load_den(const std::filesystem::path& path) {
    volume_detail::GzFile in(path);
    const std::string& file = in.file();

    const auto header = in.read_up_to(kDenHeaderBytes, "header");
    if (header.size() < 2) {
        throw InputError(file, "header",
                         fmt::format("file holds only {} bytes, a .den header needs 62", header.size()));
    }
    const std::endian order = byte_order(header, file);  // a wrong first field says more than a short header
    if (header.size() < kDenHeaderBytes) {
        throw InputError(file, "header",
                         fmt::format("file holds only {} bytes, a .den header needs 62", header.size()));
    }

    glm::ivec3 dims;
    for (std::size_t i = 0; i < 3; ++i) {
        const auto len = read_field<std::int16_t>(header, kMapLenOffset + 2 * i, order);
        volume_detail::check_axis_size(file, fmt::format("header.map_len[{}]", i), len);
        dims[static_cast<glm::length_t>(i)] = len;
    }
    const auto map_length = read_field<std::int32_t>(header, kMapLengthOffset, order);
    const std::size_t count = volume_detail::voxel_count(dims);
    if (map_length < 0 || static_cast<std::size_t>(map_length) != count) {
        throw InputError(
            file, "header.map_length",
            fmt::format("is {} but map_len {} makes {}", map_length, volume_detail::dims_text(dims), count));
    }

    check_volume_fits_host(file, "header.dims", dims, ScalarType::UInt8);
    const auto data = in.read_up_to(count, "voxel data");
    if (data.size() < count) {
        throw InputError(file, "voxel data",
                         volume_detail::size_mismatch(data.size(), dims, ScalarType::UInt8) +
                             (in.stream_cut_short() ? " (the gzip stream is cut short)" : ""));
    }
    in.require_intact_end("voxel data");
    return Volume(dims, glm::vec3(1.0f), ScalarType::UInt8,
                  volume_detail::decode_samples(data, volume_detail::SampleEncoding{}, dims, file),
                  path.filename().string());
}

}  // namespace pp5
