#include "frontends/image_io.h"

#include "frontends/image_codec/image_codec.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <dlfcn.h>

namespace pp5 {

namespace {

struct LoadedCodec {
    const image_codec::Table* table = nullptr;
    std::string why_not;  // when there is no table
};

LoadedCodec load_codec() {
    void* module = ::dlopen(image_codec::module_path(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr) {
        const char* why = ::dlerror();
        return {nullptr, why != nullptr ? why : "dlopen failed"};
    }
    const auto entry = reinterpret_cast<const image_codec::Table* (*)()>(::dlsym(module, "pp5_image_codec_table"));
    if (entry == nullptr) return {nullptr, "it has no codec table"};
    const image_codec::Table* table = entry();
    if (table->version != image_codec::kVersion)
        return {nullptr, "it was built for another version of pp5sim; rebuild it"};
    return {table, {}};
}

// The codec module, loaded once per process on first use. A failure to load is reported whenever a
// picture is asked for, not at start: the run may have other work that needs no pictures.
const image_codec::Table& codec() {
    static const LoadedCodec loaded = load_codec();
    if (loaded.table == nullptr)
        throw std::runtime_error(std::string("cannot load the image codec ") + image_codec::module_path() + ": " +
                                 loaded.why_not);
    return *loaded.table;
}

image_codec::PixelsView view_of(const std::vector<unsigned char>& rgb, const Image& image) {
    return {image.width, image.height, 3, false, rgb.data()};
}

// Colour clamped to [0, 1] as float RGB: what the comparison reads.
std::vector<float> clamped_rgb(const Image& image) {
    std::vector<float> rgb;
    rgb.reserve(image.pixels.size() * 3);
    for (const glm::vec4& p : image.pixels)
        for (int c = 0; c < 3; ++c) rgb.push_back(std::clamp(p[c], 0.0f, 1.0f));
    return rgb;
}

// Encodes `frames` (one, or several as an animation) in the format `extension` names, in memory.
std::string encode_rgb8(const std::vector<const Image*>& frames, const char* extension, float frames_per_second) {
    std::vector<std::vector<unsigned char>> bytes;
    std::vector<image_codec::PixelsView> views;
    bytes.reserve(frames.size());
    for (const Image* frame : frames) {
        bytes.push_back(to_rgb8(*frame));
        views.push_back(view_of(bytes.back(), *frame));
    }
    return codec().encode(views, extension, frames_per_second);
}

}  // namespace

std::vector<unsigned char> to_rgb8(const Image& image) {
    std::vector<unsigned char> bytes;
    bytes.reserve(image.pixels.size() * 3);
    for (const glm::vec4& p : image.pixels)
        for (int c = 0; c < 3; ++c)
            bytes.push_back(static_cast<unsigned char>(std::lround(std::clamp(p[c], 0.0f, 1.0f) * 255.0f)));
    return bytes;
}

ImageDifference compare_images(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height) {
        throw std::invalid_argument("compare_images: the images differ in size");
    }
    const std::vector<float> a = clamped_rgb(image);
    const std::vector<float> b = clamped_rgb(reference);
    return codec().compare({image.width, image.height, 3, true, a.data()},
                           {reference.width, reference.height, 3, true, b.data()});
}

Image inverted_difference(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height) {
        throw std::invalid_argument("inverted_difference: the images differ in size");
    }
    Image out(image.width, image.height);
    for (std::size_t p = 0; p < out.pixels.size(); ++p) {
        glm::vec4 v(1.0f);
        for (int c = 0; c < 3; ++c)
            v[c] = 1.0f - std::abs(std::clamp(image.pixels[p][c], 0.0f, 1.0f) -
                                   std::clamp(reference.pixels[p][c], 0.0f, 1.0f));
        out.pixels[p] = v;
    }
    return out;
}

void write_image(const Image& image, const std::filesystem::path& path, ImageFormat format) {
    if (format == ImageFormat::Png) {
        const std::vector<unsigned char> rgb = to_rgb8(image);
        codec().write_file(path, view_of(rgb, image));
    } else {
        codec().write_file(path, {image.width, image.height, 4, true, image.pixels.data()});
    }
}

std::string encode_png(const Image& image) { return encode_rgb8({&image}, "png", 0.0f); }

std::string encode_gif(const std::vector<Image>& frames, float frames_per_second) {
    if (frames.empty()) throw std::invalid_argument("encode_gif: no frames");
    std::vector<const Image*> pointers;
    for (const Image& f : frames) {
        if (f.width != frames.front().width || f.height != frames.front().height)
            throw std::invalid_argument("encode_gif: the frames differ in size");
        pointers.push_back(&f);
    }
    return encode_rgb8(pointers, "gif", frames_per_second);
}

Rgb8Picture read_rgb8(const std::filesystem::path& path) { return codec().read_rgb8(path); }

}  // namespace pp5

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PP5_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(PP5_ADDRESS_SANITIZER)
// Under AddressSanitizer, leave __tls_get_addr alone. With the codec loaded by dlopen after threads
// have started, clang 14's LeakSanitizer (Debian 12's) sometimes crashes at exit while walking those
// threads' dynamic TLS through what it intercepted ("Tracer caught signal 11"). Without the
// interception the blocks are scanned as the heap they were allocated from, reached from each thread's
// TLS; the suite reports the same (no) leaks with it. A setting in ASAN_OPTIONS overrides this default.
extern "C" const char* __asan_default_options() { return "intercept_tls_get_addr=0"; }
#endif
