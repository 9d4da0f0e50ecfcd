// InVesalius 3 projects (.inv3). The archive is read with our own small tar reader over GzFile: the
// format needs only name, size, type and checksum from each 512-byte header, and a tar library would
// be a dependency for forty lines. The plist is read just as strictly: only the few keys the volume
// needs, each checked, rather than a general XML parser.
//
// What Cranium.inv3 (invesalius-examples, written by InVesalius 3.0 beta 3) holds, and so what this
// loader was checked against: members "tmpXXXXXX/main.plist", "matrix.dat", "mask_N.{plist,dat}",
// "surface_N.{plist,vtp}" and "measurements.plist", in no order the writer promises (it globs a temp
// directory). main.plist has
//   matrix  = dict { dtype = "int16", filename = "matrix.dat", shape = [108, 256, 256] }
//   spacing = [0.957, 0.957, 1.5]
// and matrix.dat is exactly 108 * 256 * 256 * 2 bytes: a numpy memmap, headerless (not a .npy).

#include "scene/volume/inv3_io.h"

#include "scene/volume/gz_file.h"
#include "scene/volume/load_checks.h"
#include "scene/volume/sample_decode.h"
#include "sim/core/host_memory.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pp5 {

namespace {

using volume_detail::GzFile;

// ---- tar -------------------------------------------------------------------------------------------

constexpr std::size_t kTarBlock = 512;
// main.plist is a couple of kilobytes; a header claiming more is corrupt, and reading it whole first
// would cost the memory it claims.
constexpr std::size_t kMaxPlistBytes = std::size_t{1} << 20;

struct TarEntry {
    std::string name;  // the last path component: InVesalius puts every member in a temp directory
    std::size_t size = 0;
    bool regular = false;
};

// A numeric header field: octal digits, optionally led by spaces and ended by NULs or spaces (both
// conventions are in use). Anything else means the block is not what it claims to be.
std::optional<std::uint64_t> tar_octal(const char* field, std::size_t width) {
    std::size_t at = 0;
    while (at < width && field[at] == ' ') ++at;
    std::uint64_t value = 0;
    std::size_t digits = 0;
    for (; at < width && field[at] >= '0' && field[at] <= '7'; ++at, ++digits) {
        if (value > (UINT64_MAX >> 3)) return std::nullopt;
        value = value * 8 + static_cast<std::uint64_t>(field[at] - '0');
    }
    for (; at < width; ++at) {
        if (field[at] != '\0' && field[at] != ' ') return std::nullopt;
    }
    if (digits == 0) return std::nullopt;
    return value;
}

// The checksum is the sum of the header's bytes with its own 8-byte field counted as spaces. Some old
// writers summed signed chars, so either sum is accepted.
bool tar_checksum_ok(const char* header) {
    const auto stored = tar_octal(header + 148, 8);
    if (!stored) return false;
    std::uint64_t unsigned_sum = 0;
    std::int64_t signed_sum = 0;
    for (std::size_t i = 0; i < kTarBlock; ++i) {
        const bool in_field = i >= 148 && i < 156;
        unsigned_sum += in_field ? ' ' : static_cast<unsigned char>(header[i]);
        signed_sum += in_field ? ' ' : static_cast<signed char>(header[i]);
    }
    return *stored == unsigned_sum || static_cast<std::int64_t>(*stored) == signed_sum;
}

// Walks the members of a tar stream one header at a time. After next() the caller takes the
// member's data with read() or passes over it with skip(), so only the wanted member is ever held.
class TarReader {
public:
    TarReader(GzFile& gz, std::string file) : gz_(gz), file_(std::move(file)) {}

    // The next member, or nothing at the end of the archive. An archive that stops without its two
    // zero end blocks is accepted, as GNU and Python tar accept it; one that stops inside a block is not.
    std::optional<TarEntry> next() {
        const std::vector<std::byte> block = gz_.read_up_to(kTarBlock, "archive");
        if (block.size() < kTarBlock && offset_ == 0) fail("is too short for a gzipped tar (an InVesalius project)");
        if (block.empty() && !gz_.stream_cut_short()) return std::nullopt;
        if (block.size() < kTarBlock) fail("ends inside a tar header (truncated file?)");
        const char* header = reinterpret_cast<const char*>(block.data());
        const auto is_zero = [](std::byte b) { return b == std::byte{0}; };
        if (std::all_of(block.begin(), block.end(), is_zero)) return std::nullopt;  // the end-of-archive block
        if (!tar_checksum_ok(header)) {
            fail(offset_ == 0 ? "is not a gzipped tar archive (an InVesalius project): bad tar header checksum"
                              : fmt::format("bad tar header checksum at byte {} of the archive", offset_));
        }
        TarEntry entry;
        const std::string path(header, strnlen(header, 100));
        const std::size_t slash = path.rfind('/');
        entry.name = slash == std::string::npos ? path : path.substr(slash + 1);
        entry.size = member_size(header, path);
        entry.regular = header[156] == '0' || header[156] == '\0';
        offset_ += kTarBlock;
        return entry;
    }

    std::vector<std::byte> read(const TarEntry& entry) {
        // The declared size bounds what the stream may inflate to; refuse it before reading if too big.
        check_fits_host_memory(file_, "archive", static_cast<double>(entry.size), "loading member " + entry.name);
        std::vector<std::byte> data = gz_.read_up_to(entry.size, "archive");
        if (data.size() < entry.size) cut_short(entry, data.size());
        skip_bytes(padding(entry.size));  // a cut in the padding alone loses nothing; the next header tells
        offset_ += entry.size + padding(entry.size);
        return data;
    }

    void skip(const TarEntry& entry) {
        const std::size_t held = skip_bytes(entry.size);
        if (held < entry.size) cut_short(entry, held);
        skip_bytes(padding(entry.size));
        offset_ += entry.size + padding(entry.size);
    }

private:
    static std::size_t padding(std::size_t size) { return (kTarBlock - size % kTarBlock) % kTarBlock; }

    std::size_t member_size(const char* header, const std::string& path) const {
        // GNU tar writes sizes of 8 GiB and more in base 256, flagged by the top bit.
        if ((static_cast<unsigned char>(header[124]) & 0x80u) != 0)
            fail(fmt::format("member {} is 8 GiB or larger, beyond what a volume here can be", path));
        const auto size = tar_octal(header + 124, 12);
        if (!size) fail(fmt::format("member {} has a malformed size field", path));
        return static_cast<std::size_t>(*size);
    }

    // Reads and drops up to `count` bytes in bounded pieces; returns how many there were.
    std::size_t skip_bytes(std::size_t count) {
        constexpr std::size_t kPiece = std::size_t{1} << 20;
        std::size_t done = 0;
        while (done < count) {
            const std::size_t want = std::min(count - done, kPiece);
            const std::size_t got = gz_.read_up_to(want, "archive").size();
            done += got;
            if (got < want) break;
        }
        return done;
    }

    [[noreturn]] void cut_short(const TarEntry& entry, std::size_t held) const {
        fail(fmt::format("member {} holds {} of its {} bytes (truncated file?)", entry.name, held, entry.size));
    }

    [[noreturn]] void fail(const std::string& reason) const { throw InputError(file_, "archive", reason); }

    GzFile& gz_;
    std::string file_;
    std::size_t offset_ = 0;  // of the next header in the uncompressed archive, for messages
};

// The bytes of the first regular member called `name`; members are matched by their last path
// component. Each call reads the archive afresh: the members come in no set order, and holding every
// mask and surface just in case would cost several times the volume's size.
std::vector<std::byte> member_bytes(const std::filesystem::path& path, const std::string& name) {
    GzFile gz(path);
    TarReader tar(gz, path.string());
    while (const auto entry = tar.next()) {
        if (entry->regular && entry->name == name) {
            if (name == "main.plist" && entry->size > kMaxPlistBytes) {
                throw InputError(path.string(), name,
                                 fmt::format("claims {} bytes: too large for a project description", entry->size));
            }
            return tar.read(*entry);
        }
        tar.skip(*entry);
    }
    throw InputError(path.string(), name, "the archive has no such member");
}

// ---- plist -----------------------------------------------------------------------------------------

// The text inside the <tag> element that follows <key>key</key>, searching from the start of `xml`.
// Enough for InVesalius' flat main.plist, whose matrix dict holds no nested dict; not a general plist
// reader.
std::optional<std::string_view> value_after_key(std::string_view xml, std::string_view key, std::string_view tag) {
    const std::string key_element = fmt::format("<key>{}</key>", key);
    const std::size_t key_at = xml.find(key_element);
    if (key_at == std::string_view::npos) return std::nullopt;
    const std::size_t open_at = xml.find_first_not_of(" \t\r\n", key_at + key_element.size());
    const std::string open = fmt::format("<{}>", tag);
    if (open_at == std::string_view::npos || xml.substr(open_at, open.size()) != open) return std::nullopt;
    const std::size_t body_at = open_at + open.size();
    const std::size_t close_at = xml.find(fmt::format("</{}>", tag), body_at);
    if (close_at == std::string_view::npos) return std::nullopt;
    return xml.substr(body_at, close_at - body_at);
}

struct PlistItem {
    std::string_view tag;
    std::string_view text;
};

// The child elements of an <array>, in order. Nothing but whitespace may lie between them, and each
// must be a simple <tag>text</tag>; otherwise the array is not one this loader understands.
std::optional<std::vector<PlistItem>> array_items(std::string_view body) {
    std::vector<PlistItem> items;
    std::size_t at = 0;
    while ((at = body.find_first_not_of(" \t\r\n", at)) != std::string_view::npos) {
        if (body[at] != '<') return std::nullopt;
        const std::size_t tag_end = body.find('>', at);
        if (tag_end == std::string_view::npos) return std::nullopt;
        const std::string_view tag = body.substr(at + 1, tag_end - at - 1);
        if (tag.empty() || tag.find_first_of("/ ") != std::string_view::npos) return std::nullopt;
        const std::string close = fmt::format("</{}>", tag);
        const std::size_t close_at = body.find(close, tag_end + 1);
        if (close_at == std::string_view::npos) return std::nullopt;
        items.push_back({tag, body.substr(tag_end + 1, close_at - tag_end - 1)});
        at = close_at + close.size();
    }
    return items;
}

// A whole number or real, the entire text (bar surrounding whitespace) and nothing else.
template <class T>
std::optional<T> parse_number(std::string_view text) {
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos) return std::nullopt;
    text = text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
    T value{};
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

// What main.plist says about the volume.
struct Inv3Layout {
    std::string matrix_file;
    ScalarType type = ScalarType::Int16;
    glm::ivec3 dims{0};  // x, y, z
    glm::vec3 spacing{1.0f};
};

// The three items of the <array> under `key`; `what` (and `unit`) say what they should be, for the errors.
std::vector<PlistItem> three_items(std::string_view xml, const char* key, const std::string& file,
                                   const std::string& field, const char* what, const char* unit = "") {
    const auto body = value_after_key(xml, key, "array");
    if (!body) throw InputError(file, field, fmt::format("missing (an <array> of three {}{})", what, unit));
    auto items = array_items(*body);
    if (!items || items->size() != 3)
        throw InputError(file, field, fmt::format("must be an <array> of three {}", what));
    return std::move(*items);
}

// The shape is numpy's (slices, rows, columns), so it is (z, y, x) reversed.
glm::ivec3 read_shape(std::string_view matrix, const std::string& file) {
    const std::string field = "main.plist: matrix.shape";
    const auto items = three_items(matrix, "shape", file, field, "integers");
    glm::ivec3 dims{0};
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string item_field = fmt::format("{}[{}]", field, i);
        const auto value = parse_number<long long>(items[i].text);
        if (items[i].tag != "integer" || !value)
            throw InputError(file, item_field, fmt::format("'{}' is not an integer", items[i].text));
        volume_detail::check_axis_size(file, item_field, *value);
        dims[static_cast<int>(2 - i)] = static_cast<int>(*value);
    }
    return dims;
}

// Spacing is in mm and in (x, y, z) order, unlike the shape: in Cranium.inv3 the 1.5 mm slice
// distance is last while the 108 slices are first in the shape.
glm::vec3 read_spacing(std::string_view xml, const std::string& file) {
    const std::string field = "main.plist: spacing";
    const auto items = three_items(xml, "spacing", file, field, "reals", ", in mm");
    glm::vec3 spacing{1.0f};
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string item_field = fmt::format("{}[{}]", field, i);
        const auto& item = items[i];
        const auto value = parse_number<double>(item.text);
        if ((item.tag != "real" && item.tag != "integer") || !value)
            throw InputError(file, item_field, fmt::format("'{}' is not a number", item.text));
        volume_detail::check_spacing(file, item_field, *value);
        spacing[static_cast<int>(i)] = static_cast<float>(*value);
    }
    return spacing;
}

std::string_view required_string(std::string_view dict, std::string_view key, const std::string& file) {
    const auto value = value_after_key(dict, key, "string");
    if (!value || value->empty())
        throw InputError(file, fmt::format("main.plist: matrix.{}", key), "missing (a non-empty <string>)");
    return *value;
}

Inv3Layout read_layout(std::string_view xml, const std::string& file) {
    const auto matrix = value_after_key(xml, "matrix", "dict");
    if (!matrix) throw InputError(file, "main.plist: matrix", "missing (the <dict> that describes the volume)");
    Inv3Layout layout;
    const std::string_view dtype = required_string(*matrix, "dtype", file);
    const auto type = parse_scalar_type(dtype);
    if (!type) {
        throw InputError(file, "main.plist: matrix.dtype",
                         fmt::format("'{}' is not a sample type a volume can hold (int16, uint8, ...)", dtype));
    }
    layout.type = *type;
    layout.matrix_file = std::string(required_string(*matrix, "filename", file));
    layout.dims = read_shape(*matrix, file);
    layout.spacing = read_spacing(xml, file);
    return layout;
}

// Why a matrix has the wrong size, with the one likely cause spelled out: numpy's .npy header.
std::string matrix_size_problem(const std::vector<std::byte>& bytes, const Inv3Layout& layout) {
    std::string reason = volume_detail::size_mismatch(bytes.size(), layout.dims, layout.type);
    constexpr std::string_view kNpyMagic = "\x93NUMPY";
    if (bytes.size() >= kNpyMagic.size() && std::memcmp(bytes.data(), kNpyMagic.data(), kNpyMagic.size()) == 0)
        reason += " (it is a .npy file with a header; InVesalius writes a headerless numpy memmap)";
    return reason;
}

}  // namespace

Volume load_inv3(const std::filesystem::path& path) {
    const std::string file = path.string();
    volume_detail::require_regular_file(path);

    const std::vector<std::byte> plist = member_bytes(path, "main.plist");
    const Inv3Layout layout =
        read_layout(std::string_view(reinterpret_cast<const char*>(plist.data()), plist.size()), file);

    const std::vector<std::byte> matrix = member_bytes(path, layout.matrix_file);
    if (matrix.size() != volume_detail::voxel_count(layout.dims) * scalar_size_bytes(layout.type))
        throw InputError(file, layout.matrix_file, matrix_size_problem(matrix, layout));

    // The matrix is a C-order numpy array of shape (z, y, x), so x already runs fastest, as a Volume
    // wants. numpy writes native byte order and InVesalius runs on little-endian machines; the dtype
    // string ("int16") does not record the order.
    //
    // Orientation: main.plist records no slice direction, so the slices are taken in stored order.
    // For Cranium.inv3 that is already our convention: slice 0 cuts through the jaw and the head's
    // cross-section shrinks to nothing by slice 107 at the crown, so superior is +z (as in ch2); the
    // face is at high y, so anterior is +y (as in ch2). No flip is needed. Left and right cannot be told
    // apart from the data.
    volume_detail::SampleEncoding encoding;
    encoding.type = layout.type;
    encoding.order = std::endian::little;
    std::vector<float> samples = volume_detail::decode_samples(matrix, encoding, layout.dims, file);
    return Volume(layout.dims, layout.spacing, layout.type, std::move(samples), path.stem().string());
}

}  // namespace pp5
