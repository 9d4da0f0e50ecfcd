#include "kernels/volume/inv3_io.h"

#include "kernels/volume/gz_file.h"
#include "kernels/volume/load_checks.h"
#include "kernels/volume/sample_decode.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

namespace {

using volume_detail::GzFile;

// The members of a ustar archive, by name (directories dropped from the names).
std::map<std::string, std::vector<std::byte>> read_tar(GzFile& gz, const std::string& file) {
    constexpr std::size_t kBlock = 512;
    std::map<std::string, std::vector<std::byte>> members;
    for (;;) {
        const std::vector<std::byte> header = gz.read_up_to(kBlock, "archive");
        if (header.size() < kBlock) {
            if (header.empty() && !gz.stream_cut_short()) break;  // tolerated: no end-of-archive blocks
            throw InputError(file, "archive", "the tar archive ends inside a header (truncated?)");
        }
        const char* h = reinterpret_cast<const char*>(header.data());
        if (h[0] == '\0') break;  // the end-of-archive block
        std::string name(h, strnlen(h, 100));
        const std::string size_field(h + 124, strnlen(h + 124, 12));
        char* end = nullptr;
        const unsigned long long size = std::strtoull(size_field.c_str(), &end, 8);
        if (end == size_field.c_str()) throw InputError(file, "archive", fmt::format("member {} has no valid size", name));
        if (size > (1ull << 33)) throw InputError(file, "archive", fmt::format("member {} claims {} bytes", name, size));
        std::vector<std::byte> data = gz.read_up_to(static_cast<std::size_t>(size), "archive");
        if (data.size() < size) {
            throw InputError(file, "archive", fmt::format("member {} holds {} of its {} bytes (truncated?)", name, data.size(), size));
        }
        const std::size_t padding = (kBlock - size % kBlock) % kBlock;
        if (padding > 0) gz.read_up_to(padding, "archive");
        const char type = h[156];
        if (const auto slash = name.rfind('/'); slash != std::string::npos) name = name.substr(slash + 1);
        if ((type == '0' || type == '\0') && !name.empty()) members[name] = std::move(data);
    }
    return members;
}

// The text of the element that follows <key>name</key> in `xml`, if that element is a <tag>. The
// plists this loader reads nest no element of a tag inside another of the same tag.
std::optional<std::string> plist_value(const std::string& xml, const std::string& key, const std::string& tag) {
    const std::string key_element = "<key>" + key + "</key>";
    const std::size_t key_at = xml.find(key_element);
    if (key_at == std::string::npos) return std::nullopt;
    const std::size_t open_at = xml.find_first_not_of(" \t\r\n", key_at + key_element.size());
    const std::string open = "<" + tag + ">";
    if (open_at == std::string::npos || xml.compare(open_at, open.size(), open) != 0) return std::nullopt;
    const std::size_t body = open_at + open.size();
    const std::size_t close_at = xml.find("</" + tag + ">", body);
    if (close_at == std::string::npos) return std::nullopt;
    return xml.substr(body, close_at - body);
}

// The numbers of every <tag>...</tag> element in `text`, in order.
std::vector<double> numbers_in(const std::string& text, const std::string& tag) {
    std::vector<double> out;
    const std::string open = "<" + tag + ">";
    for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at + 1)) {
        out.push_back(std::strtod(text.c_str() + at + open.size(), nullptr));
    }
    return out;
}

}  // namespace

Volume load_inv3(const std::filesystem::path& path) {
    const std::string file = path.string();
    volume_detail::require_regular_file(path);
    GzFile gz(path);
    auto members = read_tar(gz, file);

    const auto main_plist = members.find("main.plist");
    if (main_plist == members.end()) throw InputError(file, "main.plist", "the archive has no main.plist");
    const std::string xml(reinterpret_cast<const char*>(main_plist->second.data()), main_plist->second.size());

    const auto matrix = plist_value(xml, "matrix", "dict");
    if (!matrix) throw InputError(file, "main.plist: matrix", "no matrix dictionary");
    const auto dtype = plist_value(*matrix, "dtype", "string");
    const auto filename = plist_value(*matrix, "filename", "string");
    const auto shape_text = plist_value(*matrix, "shape", "array");
    if (!dtype) throw InputError(file, "main.plist: matrix.dtype", "missing");
    if (!filename) throw InputError(file, "main.plist: matrix.filename", "missing");
    if (!shape_text) throw InputError(file, "main.plist: matrix.shape", "missing");
    const auto type = parse_scalar_type(*dtype);
    if (!type) throw InputError(file, "main.plist: matrix.dtype", fmt::format("unsupported type {}", *dtype));

    // The shape is (slices, rows, columns): numpy's order, so x runs fastest in the file.
    const std::vector<double> shape = numbers_in(*shape_text, "integer");
    if (shape.size() != 3) throw InputError(file, "main.plist: matrix.shape", "must hold three integers");
    const glm::ivec3 dims(static_cast<int>(shape[2]), static_cast<int>(shape[1]), static_cast<int>(shape[0]));
    for (int axis = 0; axis < 3; ++axis) {
        volume_detail::check_axis_size(file, fmt::format("main.plist: matrix.shape[{}]", 2 - axis), static_cast<long long>(shape[2 - static_cast<std::size_t>(axis)]));
    }

    glm::vec3 spacing(1.0f);
    if (const auto spacing_text = plist_value(xml, "spacing", "array")) {
        const std::vector<double> s = numbers_in(*spacing_text, "real");
        if (s.size() != 3) throw InputError(file, "main.plist: spacing", "must hold three reals");
        for (int axis = 0; axis < 3; ++axis) {
            volume_detail::check_spacing(file, fmt::format("main.plist: spacing[{}]", axis), s[static_cast<std::size_t>(axis)]);
            spacing[axis] = static_cast<float>(s[static_cast<std::size_t>(axis)]);
        }
    }

    const auto voxels = members.find(*filename);
    if (voxels == members.end()) throw InputError(file, *filename, "the archive has no such member (main.plist names it)");
    const std::size_t expected = volume_detail::voxel_count(dims) * scalar_size_bytes(*type);
    if (voxels->second.size() != expected) {
        throw InputError(file, *filename, volume_detail::size_mismatch(voxels->second.size(), dims, *type));
    }
    volume_detail::SampleEncoding encoding;
    encoding.type = *type;
    encoding.order = std::endian::little;
    std::vector<float> samples = volume_detail::decode_samples(voxels->second, encoding, dims, file);
    return Volume(dims, spacing, *type, std::move(samples), path.stem().string());
}

}  // namespace pp5
