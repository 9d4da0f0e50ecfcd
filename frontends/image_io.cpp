#include "frontends/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pp5 {

std::vector<unsigned char> to_rgb8(const Image& image) {
    std::vector<unsigned char> bytes;
    bytes.reserve(image.pixels.size() * 3);
    for (const glm::vec4& p : image.pixels)
        for (int c = 0; c < 3; ++c)
            bytes.push_back(static_cast<unsigned char>(std::lround(std::clamp(p[c], 0.0f, 1.0f) * 255.0f)));
    return bytes;
}

namespace {

OIIO::ImageBuf rgb_buffer(const Image& image) {
    std::vector<float> rgb;
    rgb.reserve(image.pixels.size() * 3);
    for (const glm::vec4& p : image.pixels)
        for (int c = 0; c < 3; ++c) rgb.push_back(std::clamp(p[c], 0.0f, 1.0f));
    OIIO::ImageBuf buffer(OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT));
    buffer.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, rgb.data());
    return buffer;
}

}  // namespace

ImageDifference compare_images(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height) {
        throw std::invalid_argument("compare_images: the images differ in size");
    }
    const OIIO::ImageBuf a = rgb_buffer(image);
    const OIIO::ImageBuf b = rgb_buffer(reference);
    const auto result = OIIO::ImageBufAlgo::compare(a, b, 1.0f, 1.0f);
    return {result.PSNR, result.rms_error, result.maxerror};
}

Image inverted_difference(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height) {
        throw std::invalid_argument("inverted_difference: the images differ in size");
    }
    Image out(image.width, image.height);
    for (std::size_t p = 0; p < out.pixels.size(); ++p) {
        glm::vec4 v(1.0f);
        for (int c = 0; c < 3; ++c)
            v[c] = 1.0f - std::abs(std::clamp(image.pixels[p][c], 0.0f, 1.0f) - std::clamp(reference.pixels[p][c], 0.0f, 1.0f));
        out.pixels[p] = v;
    }
    return out;
}

void write_image(const Image& image, const std::filesystem::path& path, ImageFormat format) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
    bool ok = false;
    if (format == ImageFormat::Png) {
        const std::vector<unsigned char> rgb = to_rgb8(image);
        const OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
        ok = out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, rgb.data());
    } else {
        OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "A"};
        ok = out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
    }
    if (!ok) throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
    if (!out->close()) throw std::runtime_error("cannot finish " + path.string() + ": " + out->geterror());
}

namespace {

// Encodes `frames` (one, or several as an animation) in the format `extension` names, in memory.
std::string encode_rgb8(const std::vector<const Image*>& frames, const char* extension, float frames_per_second) {
    const std::string name = std::string("memory.") + extension;
    OIIO::Filesystem::IOVecOutput memory;
    auto out = OIIO::ImageOutput::create(name, &memory);
    if (!out) throw std::runtime_error(std::string("cannot encode ") + extension + ": " + OIIO::geterror());
    if (frames.size() > 1 && !out->supports("multiimage"))
        throw std::runtime_error(std::string("OpenImageIO cannot write animated ") + extension);
    for (std::size_t f = 0; f < frames.size(); ++f) {
        const Image& image = *frames[f];
        OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
        if (frames.size() > 1) spec.attribute("FramesPerSecond", OIIO::TypeRational, std::vector<int>{static_cast<int>(frames_per_second * 100), 100}.data());
        void* proxy = &memory;  // the attribute holds a pointer, given by its address
        spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        const auto mode = f == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendSubimage;
        const std::vector<unsigned char> rgb = to_rgb8(image);
        if (!out->open(name, spec, mode) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()))
            throw std::runtime_error(std::string("cannot encode ") + extension + ": " + out->geterror());
    }
    if (!out->close()) throw std::runtime_error(std::string("cannot encode ") + extension + ": " + out->geterror());
    const std::vector<unsigned char>& bytes = memory.buffer();
    return std::string(bytes.begin(), bytes.end());
}

}  // namespace

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

}  // namespace pp5
