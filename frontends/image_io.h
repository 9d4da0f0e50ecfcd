#pragma once
// Writing images through OpenImageIO: 8-bit PNG for people, 32-bit float EXR for analysis. OpenImageIO
// is loaded the first time it is needed (frontends/image_codec/image_codec.h says why).

#include "scene/render/image.h"

#include <filesystem>
#include <string>
#include <vector>

namespace pp5 {

enum class ImageFormat { Png, Exr };

// Writes `image` to `path` in `format`. PNG holds RGB rounded to 8 bits (colour is already composited
// over the background); EXR holds RGBA as float. Throws std::runtime_error on failure.
void write_image(const Image& image, const std::filesystem::path& path, ImageFormat format);

// How far `image` is from `reference` in colour (RGB, each clamped to [0,1]): OpenImageIO's compare.
struct ImageDifference {
    double psnr_db = 0.0;  // peak signal-to-noise ratio, peak 1; infinite when identical
    double rms_error = 0.0;
    double max_error = 0.0;
};
// Throws std::invalid_argument if the sizes differ.
ImageDifference compare_images(const Image& image, const Image& reference);

// 1 - |image - reference| per colour channel (opaque): dark where they differ, as Wilson et al. print
// their Figure 3. Throws std::invalid_argument if the sizes differ.
Image inverted_difference(const Image& image, const Image& reference);

// The bytes of a PNG file of `image`, made in memory (to send, or to stage with other outputs).
std::string encode_png(const Image& image);
// The bytes of an animated GIF showing `frames` in turn (each the same size), looping.
std::string encode_gif(const std::vector<Image>& frames, float frames_per_second);

// The 8-bit RGB bytes a PNG of `image` holds, row 0 at the top: what tests compare.
std::vector<unsigned char> to_rgb8(const Image& image);

// A picture file decoded to 8 bits per channel, rows top to bottom.
struct Rgb8Picture {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<unsigned char> bytes;  // width * height * channels
};
// Throws std::runtime_error naming the file when it cannot be read.
Rgb8Picture read_rgb8(const std::filesystem::path& path);

}  // namespace pp5
