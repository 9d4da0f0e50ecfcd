#pragma once
// Internal to the reference renderer: runs a per-pixel function over an image in parallel tiles.
// Every pixel is computed on its own and per-tile counters are summed as integers, so the image and
// the counters are the same at any thread count.

#include "scene/render/image.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>

#include <algorithm>

namespace pp5::detail {

// pixel(px, py, counters) -> glm::vec4; Counters: default-constructible with operator+=.
template <class Counters, class PixelFn>
Counters for_each_pixel_tiled(Image& image, PixelFn&& pixel) {
    constexpr int kTile = 16;
    const int tiles_x = (image.width + kTile - 1) / kTile;
    const int tiles_y = (image.height + kTile - 1) / kTile;
    tbb::combinable<Counters> partial;
    pp5::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& r) {
        Counters& local = partial.local();
        for (int tile = r.begin(); tile != r.end(); ++tile) {
            const int x0 = (tile % tiles_x) * kTile;
            const int y0 = (tile / tiles_x) * kTile;
            const int x1 = std::min(x0 + kTile, image.width);
            const int y1 = std::min(y0 + kTile, image.height);
            for (int y = y0; y < y1; ++y) {
                for (int x = x0; x < x1; ++x) image.at(x, y) = pixel(x, y, local);
            }
        }
    });
    Counters total{};
    partial.combine_each([&](const Counters& c) { total += c; });
    return total;
}

}  // namespace pp5::detail
