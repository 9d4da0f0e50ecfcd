#pragma once
// Writing images through OpenImageIO: 8-bit PNG for people, 32-bit float EXR for analysis.

#include "kernels/render/image.h"

#include <filesystem>

namespace pp5 {

enum class ImageFormat { Png, Exr };

// Writes `image` to `path` in `format`. PNG holds RGB rounded to 8 bits (colour is already composited
// over the background); EXR holds RGBA as float. Throws std::runtime_error on failure.
void write_image(const Image& image, const std::filesystem::path& path, ImageFormat format);

// The 8-bit RGB bytes a PNG of `image` holds, row 0 at the top: what tests compare.
std::vector<unsigned char> to_rgb8(const Image& image);

}  // namespace pp5
