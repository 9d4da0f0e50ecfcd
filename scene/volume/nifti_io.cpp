// NIfTI-1 single-file reader (.nii, .nii.gz).
//
// The 348-byte header is parsed here rather than through libnifti (libnifti2-dev) on purpose:
// libnifti reports problems on stderr and answers with a null pointer, so the user would see its
// noise and we could not say which field is wrong; it also accepts files we must refuse (4D series,
// NaN samples). Reading the dozen fields a scalar volume needs is short, and every refusal can then
// name the field and the reason.

#include "scene/volume/volume_io.h"

#include "scene/volume/byte_fields.h"
#include "scene/volume/gz_file.h"
#include "scene/volume/load_checks.h"
#include "scene/volume/sample_decode.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

namespace pp5 {

namespace {

using volume_detail::read_field;

constexpr std::size_t kNiftiHeaderBytes = 348;

// Byte offsets of the header fields read here (nifti1.h, struct nifti_1_header).
namespace offset {
constexpr std::size_t sizeof_hdr = 0;
constexpr std::size_t dim = 40;  // short[8]
constexpr std::size_t datatype = 70;
constexpr std::size_t pixdim = 76;  // float[8]
constexpr std::size_t vox_offset = 108;
constexpr std::size_t scl_slope = 112;
constexpr std::size_t scl_inter = 116;
constexpr std::size_t xyzt_units = 123;
constexpr std::size_t magic = 344;  // char[4]
}  // namespace offset

struct DatatypeCode {
    std::int16_t code;
    std::optional<ScalarType> type;  // empty: a NIfTI type pp5sim does not read
    std::string_view name;
};

constexpr std::array<DatatypeCode, 17> kDatatypes{{
    {2, ScalarType::UInt8, "uint8"},
    {4, ScalarType::Int16, "int16"},
    {8, ScalarType::Int32, "int32"},
    {16, ScalarType::Float32, "float32"},
    {64, ScalarType::Float64, "float64"},
    {256, ScalarType::Int8, "int8"},
    {512, ScalarType::UInt16, "uint16"},
    {768, ScalarType::UInt32, "uint32"},
    {0, std::nullopt, "unknown"},
    {1, std::nullopt, "binary"},
    {32, std::nullopt, "complex64"},
    {128, std::nullopt, "RGB24"},
    {1024, std::nullopt, "int64"},
    {1280, std::nullopt, "uint64"},
    {1536, std::nullopt, "float128"},
    {1792, std::nullopt, "complex128"},
    {2304, std::nullopt, "RGBA32"},
}};

ScalarType scalar_type_of(std::int16_t code, const std::string& file) {
    for (const auto& entry : kDatatypes) {
        if (entry.code != code) continue;
        if (entry.type) return *entry.type;
        throw InputError(file, "header.datatype",
                         fmt::format("is {} ({}): only scalar volumes of uint8 (2), int8 (256), uint16 (512), "
                                     "int16 (4), uint32 (768), int32 (8), float32 (16) or float64 (64) are read",
                                     code, entry.name));
    }
    throw InputError(file, "header.datatype", fmt::format("is {}: not a NIfTI-1 datatype code", code));
}

std::endian header_byte_order(std::span<const std::byte> header, const std::string& file) {
    const auto little = read_field<std::int32_t>(header, offset::sizeof_hdr, std::endian::little);
    const auto big = read_field<std::int32_t>(header, offset::sizeof_hdr, std::endian::big);
    // A writer stores the header in its own byte order; sizeof_hdr tells which.
    if (little == static_cast<std::int32_t>(kNiftiHeaderBytes)) return std::endian::little;
    if (big == static_cast<std::int32_t>(kNiftiHeaderBytes)) return std::endian::big;
    if (little == 540 || big == 540)
        throw InputError(file, "header.sizeof_hdr", "is 540: a NIfTI-2 file; only NIfTI-1 is read");
    throw InputError(file, "header.sizeof_hdr",
                     fmt::format("is {}: a NIfTI-1 header has 348 (is this a NIfTI-1 file?)", little));
}

std::string printable(std::span<const std::byte> bytes) {
    std::string text;
    for (const std::byte b : bytes) {
        const auto c = static_cast<unsigned char>(b);
        text += (c >= 0x20 && c < 0x7f) ? std::string(1, static_cast<char>(c)) : fmt::format("\\x{:02x}", c);
    }
    return text;
}

void check_magic(std::span<const std::byte> header, const std::string& file) {
    const auto magic = header.subspan(offset::magic, 4);
    const std::string text = printable(magic);
    if (text == "n+1\\x00") return;
    if (text == "ni1\\x00") {
        throw InputError(file, "header.magic",
                         "is \"ni1\": the header of a .hdr/.img pair; only single-file NIfTI-1 (\"n+1\") is read");
    }
    throw InputError(file, "header.magic", "is \"" + text + "\": a single-file NIfTI-1 header has \"n+1\"");
}

glm::ivec3 read_dims(std::span<const std::byte> header, std::endian order, const std::string& file) {
    std::array<std::int16_t, 8> dim{};
    for (std::size_t i = 0; i < dim.size(); ++i) dim[i] = read_field<std::int16_t>(header, offset::dim + 2 * i, order);
    if (dim[0] < 3 || dim[0] > 7) {
        throw InputError(file, "header.dim[0]",
                         fmt::format("is {}: a volume needs 3 dimensions (more only if each extra one is 1)", dim[0]));
    }
    for (std::size_t i = 4; i <= static_cast<std::size_t>(dim[0]); ++i) {
        if (dim[i] != 1) {
            throw InputError(
                file, fmt::format("header.dim[{}]", i),
                fmt::format("is {}: only a single 3D volume is read, not a series or vector data", dim[i]));
        }
    }
    for (std::size_t i = 1; i <= 3; ++i) volume_detail::check_axis_size(file, fmt::format("header.dim[{}]", i), dim[i]);
    return {dim[1], dim[2], dim[3]};
}

// pixdim in mm, the unit Volume::spacing() promises; xyzt_units says what the file used.
glm::vec3 read_spacing(std::span<const std::byte> header, std::endian order, const std::string& file) {
    const auto units = static_cast<unsigned>(header[offset::xyzt_units]) & 0x07u;
    const double to_mm = units == 1 ? 1000.0 : units == 3 ? 0.001 : 1.0;  // 1 metre, 2 mm, 3 micron, 0 unknown
    glm::vec3 spacing(1.0f);
    for (std::size_t i = 1; i <= 3; ++i) {
        const auto p = static_cast<double>(read_field<float>(header, offset::pixdim + 4 * i, order));
        if (p == 0.0) continue;  // NIfTI's "unknown"; unit spacing is the only sensible reading
        volume_detail::check_spacing(file, fmt::format("header.pixdim[{}]", i), p);
        spacing[static_cast<glm::length_t>(i - 1)] = static_cast<float>(p * to_mm);
    }
    return spacing;
}

std::size_t read_vox_offset(std::span<const std::byte> header, std::endian order, const std::string& file) {
    const auto v = static_cast<double>(read_field<float>(header, offset::vox_offset, order));
    if (!std::isfinite(v) || v != std::floor(v))
        throw InputError(file, "header.vox_offset", fmt::format("is {}: must be a whole byte offset", v));
    if (v < static_cast<double>(kNiftiHeaderBytes)) {
        throw InputError(file, "header.vox_offset",
                         fmt::format("is {}: in a single-file NIfTI-1 the samples start at byte 348 or later "
                                     "(usually 352)",
                                     v));
    }
    // Past 2^53 bytes a double no longer counts whole bytes, and no file is that long anyway.
    constexpr double kLongestFile = 9007199254740992.0;
    if (v > kLongestFile)
        throw InputError(file, "header.vox_offset", fmt::format("is {}: past the end of any file", v));
    return static_cast<std::size_t>(v);
}

volume_detail::SampleEncoding read_encoding(std::span<const std::byte> header, std::endian order, ScalarType type) {
    volume_detail::SampleEncoding e;
    e.type = type;
    e.order = order;
    const auto slope = static_cast<double>(read_field<float>(header, offset::scl_slope, order));
    const auto inter = static_cast<double>(read_field<float>(header, offset::scl_inter, order));
    // NIfTI-1: slope 0 means no scaling; nibabel writes NaN for the same.
    if (std::isfinite(slope) && slope != 0.0) {
        e.slope = slope;
        e.intercept = std::isfinite(inter) ? inter : 0.0;
    }
    return e;
}

std::string cut_short_note(const volume_detail::GzFile& in) {
    return in.stream_cut_short() ? " (the gzip stream is cut short)" : "";
}

}  // namespace

Volume load_nifti(const std::filesystem::path& path) {
    volume_detail::GzFile in(path);
    const std::string& file = in.file();

    const auto header = in.read_up_to(kNiftiHeaderBytes, "header");
    if (header.size() < kNiftiHeaderBytes) {
        throw InputError(
            file, "header",
            fmt::format("file holds only {} bytes, a NIfTI-1 header needs 348{}", header.size(), cut_short_note(in)));
    }
    const std::endian order = header_byte_order(header, file);
    check_magic(header, file);
    const glm::ivec3 dims = read_dims(header, order, file);
    const ScalarType type = scalar_type_of(read_field<std::int16_t>(header, offset::datatype, order), file);
    const glm::vec3 spacing = read_spacing(header, order, file);
    const std::size_t vox_offset = read_vox_offset(header, order, file);
    const volume_detail::SampleEncoding encoding = read_encoding(header, order, type);

    // Extensions, if any, lie between the header and vox_offset; nothing in them is needed.
    const std::size_t gap = vox_offset - kNiftiHeaderBytes;
    if (in.read_up_to(gap, "header.vox_offset").size() < gap) {
        throw InputError(file, "header.vox_offset",
                         fmt::format("is {} but the file ends before it{}", vox_offset, cut_short_note(in)));
    }
    const std::size_t need = volume_detail::voxel_count(dims) * scalar_size_bytes(type);
    check_volume_fits_host(file, "header.dim", dims, type);
    const auto data = in.read_up_to(need, "voxel data");
    if (data.size() < need)
        throw InputError(file, "voxel data",
                         volume_detail::size_mismatch(data.size(), dims, type) + cut_short_note(in));
    in.require_intact_end("voxel data");

    return Volume(dims, spacing, type, volume_detail::decode_samples(data, encoding, dims, file),
                  path.filename().string());
}

}  // namespace pp5
