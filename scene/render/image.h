#pragma once
// A floating-point RGBA image, the output of every renderer. Row 0 is the top of the picture.

#include <glm/vec4.hpp>

#include <cstddef>
#include <vector>

namespace pp5 {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<glm::vec4> pixels;  // width * height, row-major; colour is not premultiplied by alpha

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h)) {}
    glm::vec4& at(int x, int y) {
        return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
    }
    const glm::vec4& at(int x, int y) const {
        return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
    }
};

}  // namespace pp5
