// Headerless raw volumes: the layout comes from the caller, so the file size is the only check that
// the layout is right, and it is applied strictly in both directions.

#include "scene/volume/volume_io.h"

#include "scene/volume/load_checks.h"
#include "scene/volume/sample_decode.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <system_error>
#include <vector>

namespace pp5 {

namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

void check_layout(const std::string& file, const RawLayout& layout) {
    const char* axes[] = {"dims.x", "dims.y", "dims.z"};
    const char* spacing_axes[] = {"spacing.x", "spacing.y", "spacing.z"};
    for (glm::length_t i = 0; i < 3; ++i) volume_detail::check_axis_size(file, axes[i], layout.dims[i]);
    for (glm::length_t i = 0; i < 3; ++i)
        volume_detail::check_spacing(file, spacing_axes[i], static_cast<double>(layout.spacing[i]));
}

}  // namespace

Volume load_raw(const std::filesystem::path& path, const RawLayout& layout) {
    const std::string file = path.string();
    check_layout(file, layout);
    volume_detail::require_regular_file(path);

    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(file, "file", "cannot be examined: " + ec.message());
    if (size < layout.header_bytes) {
        throw InputError(file, "header_bytes",
                         fmt::format("is {} but the file holds only {} bytes", layout.header_bytes, size));
    }
    const std::size_t held = static_cast<std::size_t>(size) - layout.header_bytes;
    const std::size_t need = volume_detail::voxel_count(layout.dims) * scalar_size_bytes(layout.type);
    if (held != need) {
        throw InputError(file, "voxel data",
                         volume_detail::size_mismatch(held, layout.dims, layout.type) +
                             (held < need ? "" : ": check dims, type and header_bytes"));
    }

    // Plain stdio, not zlib's transparent reader: raw samples may begin with the gzip magic bytes.
    errno = 0;
    const std::unique_ptr<std::FILE, FileCloser> in(std::fopen(path.c_str(), "rb"));
    if (!in) throw InputError(file, "file", std::string("cannot be opened: ") + std::strerror(errno));
    check_volume_fits_host(file, "dims", layout.dims, layout.type);
    std::vector<std::byte> data(need);
    if (std::fseek(in.get(), static_cast<long>(layout.header_bytes), SEEK_SET) != 0 ||
        std::fread(data.data(), 1, need, in.get()) != need) {
        throw InputError(file, "voxel data", std::string("read failed: ") + std::strerror(errno));
    }

    volume_detail::SampleEncoding encoding;
    encoding.type = layout.type;
    encoding.order = layout.big_endian ? std::endian::big : std::endian::little;
    return Volume(layout.dims, layout.spacing, layout.type,
                  volume_detail::decode_samples(data, encoding, layout.dims, file), path.filename().string());
}

}  // namespace pp5
