#pragma once
// The bytes of each volume file format the loaders read, spelled out here from the formats' own
// definitions and independently of the loaders: the loader tests write them to read back, and the
// fuzzing harnesses' seed corpora start from them. No test framework here, so any program may use it.

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pp5::test {

using Bytes = std::vector<std::byte>;

template <class T>
void append(Bytes& out, T value, std::endian order = std::endian::little) {
    auto raw = std::bit_cast<std::array<std::byte, sizeof(T)>>(value);
    if (order != std::endian::native) std::reverse(raw.begin(), raw.end());
    out.insert(out.end(), raw.begin(), raw.end());
}

template <class T>
Bytes sample_bytes(const std::vector<T>& values, std::endian order = std::endian::little) {
    Bytes out;
    for (const T v : values) append(out, v, order);
    return out;
}

// The fields of a NIfTI-1 header the loader reads, with the defaults of a valid 3D uint8 file.
struct NiftiSpec {
    std::int32_t sizeof_hdr = 348;
    std::array<std::int16_t, 8> dim{3, 1, 1, 1, 1, 1, 1, 1};
    std::int16_t datatype = 2;
    std::int16_t bitpix = 8;
    std::array<float, 8> pixdim{1, 1, 1, 1, 1, 1, 1, 1};
    float vox_offset = 352;
    float scl_slope = 0;
    float scl_inter = 0;
    std::uint8_t xyzt_units = 2;  // mm
    std::array<char, 4> magic{'n', '+', '1', '\0'};
    std::endian order = std::endian::little;

    void set_dims(int x, int y, int z) {
        dim[1] = static_cast<std::int16_t>(x);
        dim[2] = static_cast<std::int16_t>(y);
        dim[3] = static_cast<std::int16_t>(z);
    }
};

// Header at the offsets of nifti1.h's struct nifti_1_header, zero padding up to vox_offset, samples.
inline Bytes nifti_bytes(const NiftiSpec& s, const Bytes& samples) {
    Bytes out;
    append(out, s.sizeof_hdr, s.order);
    out.resize(40);
    for (const auto d : s.dim) append(out, d, s.order);  // 40
    out.resize(70);
    append(out, s.datatype, s.order);  // 70
    append(out, s.bitpix, s.order);    // 72
    out.resize(76);
    for (const auto p : s.pixdim) append(out, p, s.order);  // 76
    append(out, s.vox_offset, s.order);                     // 108
    append(out, s.scl_slope, s.order);                      // 112
    append(out, s.scl_inter, s.order);                      // 116
    out.resize(123);
    out.push_back(static_cast<std::byte>(s.xyzt_units));  // 123
    out.resize(344);
    for (const char c : s.magic) out.push_back(static_cast<std::byte>(c));  // 344
    if (out.size() != 348) throw std::logic_error("nifti_bytes: the header is not 348 bytes");
    if (s.vox_offset >= 348) out.resize(static_cast<std::size_t>(s.vox_offset));
    out.insert(out.end(), samples.begin(), samples.end());
    return out;
}

// A .den file laid out as denfile.c's write_den does, in the given byte order.
inline Bytes den_bytes(glm::ivec3 dims, const Bytes& samples, std::endian order = std::endian::little,
                       std::int16_t version = 1) {
    Bytes out;
    append(out, version, order);
    const auto d = [](int v) { return static_cast<std::int16_t>(v); };
    for (int group = 0; group < 3; ++group) {                            // orig, extr, map
        for (int i = 0; i < 3; ++i) append(out, d(0), order);            // min
        for (int i = 0; i < 3; ++i) append(out, d(dims[i] - 1), order);  // max
        for (int i = 0; i < 3; ++i) append(out, d(dims[i]), order);      // len
    }
    append(out, d(0), order);  // map_warps
    append(out, static_cast<std::int32_t>(dims.x * dims.y * dims.z), order);
    if (out.size() != 62) throw std::logic_error("den_bytes: the header is not 62 bytes");
    out.insert(out.end(), samples.begin(), samples.end());
    return out;
}

// InVesalius .inv3: a gzipped ustar archive of main.plist and the matrix (gzip is the caller's).
using Members = std::vector<std::pair<std::string, Bytes>>;

inline Bytes text_bytes(const std::string& s) {
    Bytes b(s.size());
    std::memcpy(b.data(), s.data(), s.size());
    return b;
}

constexpr std::size_t kBlock = 512;

inline std::size_t padded(std::size_t size) { return (size + kBlock - 1) / kBlock * kBlock; }

// Rewrites the checksum of the header at `at`: the unsigned sum of its bytes with the checksum field
// itself counted as eight spaces, as six octal digits, a NUL and a space.
inline void set_checksum(Bytes& archive, std::size_t at) {
    std::memset(archive.data() + at + 148, ' ', 8);
    unsigned sum = 0;
    for (std::size_t i = 0; i < kBlock; ++i) sum += static_cast<unsigned char>(archive[at + i]);
    char field[8];
    std::snprintf(field, sizeof field, "%06o", sum);
    std::memcpy(archive.data() + at + 148, field, 7);  // six digits and their NUL; the space stays
}

// A ustar archive of the members in order, each under a directory as InVesalius writes them, ended
// by the two zero blocks.
inline Bytes tar(const Members& members) {
    Bytes out;
    for (const auto& [name, data] : members) {
        const std::size_t at = out.size();
        out.resize(at + kBlock);
        char* header = reinterpret_cast<char*>(out.data() + at);
        const std::string path = "tmpq3x9zk/" + name;
        std::memcpy(header, path.data(), path.size());
        std::snprintf(header + 100, 8, "%07o", 0644u);                                 // mode
        std::snprintf(header + 124, 12, "%011o", static_cast<unsigned>(data.size()));  // size
        header[156] = '0';                                                             // regular file
        std::memcpy(header + 257, "ustar", 6);
        std::memcpy(header + 263, "00", 2);
        set_checksum(out, at);
        out.insert(out.end(), data.begin(), data.end());
        out.resize(padded(out.size()));
    }
    out.resize(out.size() + 2 * kBlock);
    return out;
}

// The keys of main.plist the loader reads; an absent value leaves the key out.
struct PlistSpec {
    std::optional<std::string> dtype = "int16";
    std::optional<std::string> filename = "matrix.dat";
    std::optional<std::string> shape = "<integer>3</integer><integer>4</integer><integer>5</integer>";
    std::optional<std::string> spacing = "<real>0.5</real>\n<real>0.75</real>\n<integer>2</integer>";
    bool matrix_dict = true;
};

// Laid out as Python's plistlib writes it, with keys the loader ignores around the ones it reads.
inline std::string plist(const PlistSpec& s = {}) {
    std::string matrix;
    if (s.dtype) matrix += "\t\t<key>dtype</key>\n\t\t<string>" + *s.dtype + "</string>\n";
    if (s.filename) matrix += "\t\t<key>filename</key>\n\t\t<string>" + *s.filename + "</string>\n";
    if (s.shape) matrix += "\t\t<key>shape</key>\n\t\t<array>\n" + *s.shape + "\n\t\t</array>\n";
    std::string xml =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<plist version=\"1.0\">\n<dict>\n"
        "\t<key>masks</key>\n\t<dict>\n\t\t<key>0</key>\n"
        "\t\t<string>mask_0.plist</string>\n\t</dict>\n";
    if (s.matrix_dict) xml += "\t<key>matrix</key>\n\t<dict>\n" + matrix + "\t</dict>\n";
    xml += "\t<key>modality</key>\n\t<string>CT</string>\n";
    if (s.spacing) xml += "\t<key>spacing</key>\n\t<array>\n" + *s.spacing + "\n\t</array>\n";
    return xml + "\t<key>window_level</key>\n\t<real>-18.0</real>\n</dict>\n</plist>\n";
}

}  // namespace pp5::test
