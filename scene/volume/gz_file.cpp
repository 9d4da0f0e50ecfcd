#include "scene/volume/gz_file.h"

#include "scene/volume/load_checks.h"
#include "sim/core/input_error.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace pp5::volume_detail {

namespace {

gzFile as_gz(void* handle) { return static_cast<gzFile>(handle); }

// Reads start at 64 KiB and double up to 16 MiB: large reads keep zlib's per-call overhead negligible
// on 100 MB volumes, and a header that declares more than its small file holds costs a small read,
// not megabytes zero-filled and thrown away (what made each fuzzing run of a reader take 2 ms).
constexpr std::size_t kFirstChunkBytes = std::size_t{64} << 10;
constexpr std::size_t kChunkBytes = std::size_t{16} << 20;
// zlib's input buffer (and its output buffer, twice that): 256 KiB for a large file, no more than
// the file for a small one.
constexpr std::uintmax_t kLeastBufferBytes = 8u << 10;
constexpr std::uintmax_t kMostBufferBytes = 256u << 10;

}  // namespace

GzFile::GzFile(const std::filesystem::path& path) : file_(path.string()) {
    require_regular_file(path);
    errno = 0;
    gzFile gz = gzopen(path.c_str(), "rb");
    if (gz == nullptr) {
        throw InputError(file_, "file",
                         std::string("cannot be opened: ") + (errno != 0 ? std::strerror(errno) : "out of memory"));
    }
    std::error_code size_error;
    const std::uintmax_t file_bytes = std::filesystem::file_size(path, size_error);
    const std::uintmax_t buffer =
        size_error ? kMostBufferBytes : std::clamp(file_bytes, kLeastBufferBytes, kMostBufferBytes);
    gzbuffer(gz, static_cast<unsigned>(buffer));
    handle_ = gz;
}

GzFile::~GzFile() {
    if (handle_ != nullptr) gzclose(as_gz(handle_));
}

std::vector<std::byte> GzFile::read_up_to(std::size_t count, const std::string& field) {
    std::vector<std::byte> out;
    out.reserve(std::min(count, kFirstChunkBytes));
    while (out.size() < count) {
        const std::size_t chunk = std::clamp(out.size(), kFirstChunkBytes, kChunkBytes);
        const std::size_t want = std::min(count - out.size(), chunk);
        const std::size_t at = out.size();
        out.resize(at + want);
        const int got = gzread(as_gz(handle_), out.data() + at, static_cast<unsigned>(want));
        if (got < 0) {
            int code = Z_OK;
            const char* message = gzerror(as_gz(handle_), &code);
            if (code == Z_ERRNO) throw InputError(file_, field, std::string("read failed: ") + std::strerror(errno));
            throw InputError(file_, field, std::string("gzip data is corrupt: ") + message);
        }
        out.resize(at + static_cast<std::size_t>(got));
        if (static_cast<std::size_t>(got) < want) {
            int code = Z_OK;
            gzerror(as_gz(handle_), &code);
            cut_short_ = cut_short_ || code == Z_BUF_ERROR;
            break;
        }
    }
    return out;
}

void GzFile::require_intact_end(const std::string& field) {
    if (gzdirect(as_gz(handle_)) != 0) return;  // not compressed: no trailer to check
    // One byte more makes zlib reach the trailer if the stream ends here, and check it.
    char probe = 0;
    const int got = gzread(as_gz(handle_), &probe, 1);
    int code = Z_OK;
    const char* message = gzerror(as_gz(handle_), &code);
    if (got < 0 && code != Z_BUF_ERROR) throw InputError(file_, field, std::string("gzip data is corrupt: ") + message);
    if (got <= 0 && code == Z_BUF_ERROR)
        throw InputError(file_, field, "the gzip stream ends without its trailer (the file is cut short)");
}

}  // namespace pp5::volume_detail
