#include "scene/volume/gz_file.h"

#include "scene/volume/load_checks.h"
#include "sim/core/input_error.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace pp5::volume_detail {

namespace {

gzFile as_gz(void* handle) { return static_cast<gzFile>(handle); }

// Large reads keep zlib's per-call overhead negligible on 100 MB volumes; the cap bounds what a
// lying header can make us reserve up front.
constexpr std::size_t kChunkBytes = std::size_t{16} << 20;

}  // namespace

GzFile::GzFile(const std::filesystem::path& path) : file_(path.string()) {
    require_regular_file(path);
    errno = 0;
    gzFile gz = gzopen(path.c_str(), "rb");
    if (gz == nullptr) {
        throw InputError(file_, "file",
                         std::string("cannot be opened: ") + (errno != 0 ? std::strerror(errno) : "out of memory"));
    }
    gzbuffer(gz, 1u << 18);
    handle_ = gz;
}

GzFile::~GzFile() {
    if (handle_ != nullptr) gzclose(as_gz(handle_));
}

std::vector<std::byte> GzFile::read_up_to(std::size_t count, const std::string& field) {
    std::vector<std::byte> out;
    out.reserve(std::min(count, kChunkBytes));
    while (out.size() < count) {
        const std::size_t want = std::min(count - out.size(), kChunkBytes);
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
