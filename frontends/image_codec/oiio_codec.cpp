// The image codec module: OpenImageIO behind the table image_io.cpp loads (image_codec.h).

#include "frontends/image_codec/image_codec.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <stdexcept>

namespace pp5::image_codec {
namespace {

OIIO::TypeDesc type_of(const PixelsView& pixels) {
    return pixels.floating ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
}

OIIO::ImageSpec spec_of(const PixelsView& pixels) {
    OIIO::ImageSpec spec(pixels.width, pixels.height, pixels.channels, type_of(pixels));
    if (pixels.channels == 4) spec.channelnames = {"R", "G", "B", "A"};
    // zlib's fastest level: a frame's pictures are written (and, in serve, sent) every frame, and level
    // 1 encodes a 512x512 frame in a fraction of the default's time for files 10-30% larger. Other
    // formats ignore it.
    spec.attribute("png:compressionLevel", 1);
    return spec;
}

void write_file(const std::filesystem::path& path, const PixelsView& pixels) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
    if (!out->open(path.string(), spec_of(pixels)) || !out->write_image(type_of(pixels), pixels.data))
        throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
    if (!out->close()) throw std::runtime_error("cannot finish " + path.string() + ": " + out->geterror());
}

std::string encode(const std::vector<PixelsView>& frames, const char* extension, float frames_per_second) {
    const std::string name = std::string("memory.") + extension;
    OIIO::Filesystem::IOVecOutput memory;
    auto out = OIIO::ImageOutput::create(name, &memory);
    if (!out) throw std::runtime_error(std::string("cannot encode ") + extension + ": " + OIIO::geterror());
    if (frames.size() > 1 && !out->supports("multiimage"))
        throw std::runtime_error(std::string("OpenImageIO cannot write animated ") + extension);
    for (std::size_t f = 0; f < frames.size(); ++f) {
        OIIO::ImageSpec spec = spec_of(frames[f]);
        if (frames.size() > 1) {
            const int rate[2] = {static_cast<int>(frames_per_second * 100), 100};
            spec.attribute("FramesPerSecond", OIIO::TypeRational, rate);
        }
        void* proxy = &memory;  // the attribute holds a pointer, given by its address
        spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        const auto mode = f == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendSubimage;
        if (!out->open(name, spec, mode) || !out->write_image(type_of(frames[f]), frames[f].data))
            throw std::runtime_error(std::string("cannot encode ") + extension + ": " + out->geterror());
    }
    if (!out->close()) throw std::runtime_error(std::string("cannot encode ") + extension + ": " + out->geterror());
    const std::vector<unsigned char>& bytes = memory.buffer();
    return std::string(bytes.begin(), bytes.end());
}

OIIO::ImageBuf buffer_of(const PixelsView& pixels) {
    OIIO::ImageBuf buffer(spec_of(pixels));
    buffer.set_pixels(OIIO::ROI::All(), type_of(pixels), pixels.data);
    return buffer;
}

ImageDifference compare(const PixelsView& image, const PixelsView& reference) {
    const auto result = OIIO::ImageBufAlgo::compare(buffer_of(image), buffer_of(reference), 1.0f, 1.0f);
    return {result.PSNR, result.rms_error, result.maxerror};
}

Rgb8Picture read_rgb8(const std::filesystem::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw std::runtime_error("cannot read " + path.string() + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    Rgb8Picture decoded{spec.width, spec.height, spec.nchannels, {}};
    decoded.bytes.resize(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) *
                         static_cast<std::size_t>(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, decoded.bytes.data()))
        throw std::runtime_error("cannot read " + path.string() + ": " + in->geterror());
    return decoded;
}

const Table kTable{kVersion, write_file, encode, compare, read_rgb8};

}  // namespace
}  // namespace pp5::image_codec

extern "C" const pp5::image_codec::Table* pp5_image_codec_table() { return &pp5::image_codec::kTable; }
