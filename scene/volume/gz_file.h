#pragma once
// A file read through zlib: gzip-compressed or plain, told apart by zlib from the first bytes, so one
// loader serves both "x.nii" and "x.nii.gz". Internal to scene/volume.
//
// Only for formats whose first bytes can never be the gzip magic (1f 8b): a NIfTI-1 header starts
// with sizeof_hdr 348, a .den file with version 1. Raw files can start with anything and are read
// with plain stdio instead.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pp5::volume_detail {

class GzFile {
public:
    // Throws InputError(file, "file", ...) if the file is missing, not a regular file or unreadable.
    explicit GzFile(const std::filesystem::path& path);
    ~GzFile();
    GzFile(const GzFile&) = delete;
    GzFile& operator=(const GzFile&) = delete;

    // Reads up to `count` bytes, fewer only where the data ends. The buffer grows as data arrives,
    // so a header that claims a huge volume costs memory only for the bytes the file really holds.
    // Throws InputError(file, field, ...) if the compressed stream is corrupt.
    std::vector<std::byte> read_up_to(std::size_t count, const std::string& field);

    // After the last read a loader needs: throws InputError(file, field, ...) if a gzip stream ends
    // right there without its trailer (a download cut just short of its end) or the trailer's
    // checksum or length disagrees with the data. Data after what the loader read is not examined.
    void require_intact_end(const std::string& field);

    // True once a read has met the end of a gzip stream cut short (a truncated download).
    bool stream_cut_short() const { return cut_short_; }

    const std::string& file() const { return file_; }

private:
    std::string file_;
    void* handle_ = nullptr;  // gzFile, kept opaque so zlib.h stays out of the loaders' headers
    bool cut_short_ = false;
};

}  // namespace pp5::volume_detail
