#include "kernels/levoy/adaptive_refinement.h"
#include "sim/core/parallel.h"

#include <algorithm>
#include <stdexcept>

namespace pp5 {

namespace {
// 0, s, 2s, ... and the last index, so the lattice spans [0, n-1].
std::vector<int> lattice(int n, int spacing) {
    std::vector<int> at;
    for (int i = 0; i < n; i += spacing) at.push_back(i);
    if (at.back() != n - 1) at.push_back(n - 1);
    return at;
}
// The lattice's intervals; a one-pixel extent gives one zero-width interval.
std::vector<std::pair<int, int>> intervals(const std::vector<int>& at) {
    std::vector<std::pair<int, int>> out;
    if (at.size() == 1) out.emplace_back(at[0], at[0]);
    for (std::size_t i = 0; i + 1 < at.size(); ++i) out.emplace_back(at[i], at[i + 1]);
    return out;
}
}  // namespace

AdaptiveRefinement::AdaptiveRefinement(int width, int height, RefinementSettings settings)
    : width_(width), height_(height), settings_(settings) {
    if (width < 1 || height < 1) throw std::invalid_argument("adaptive refinement: empty image");
    if (settings.initial_spacing < 1) throw std::invalid_argument("adaptive refinement: spacing below one pixel");
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    colors_.assign(n, glm::vec4(0.0f));
    cast_.assign(n, 0);
    const auto xs = lattice(width, settings.initial_spacing);
    const auto ys = lattice(height, settings.initial_spacing);
    for (int y : ys)
        for (int x : xs) pending_.push_back(index(x, y));
    for (const auto& [y0, y1] : intervals(ys))
        for (const auto& [x0, x1] : intervals(xs)) active_.push_back(Square{x0, y0, x1, y1});
}

bool AdaptiveRefinement::needs_split(const Square& s) const {
    if (s.x1 - s.x0 < 2 && s.y1 - s.y0 < 2) return false;
    if (settings_.threshold < 0.0f) return true;
    const glm::vec4 c[4] = {colors_[index(s.x0, s.y0)], colors_[index(s.x1, s.y0)], colors_[index(s.x0, s.y1)],
                            colors_[index(s.x1, s.y1)]};
    for (int channel = 0; channel < 3; ++channel) {
        float lo = c[0][channel];
        float hi = lo;
        for (const auto& corner : c) {
            lo = std::min(lo, corner[channel]);
            hi = std::max(hi, corner[channel]);
        }
        if (hi - lo > settings_.threshold) return true;
    }
    return false;
}

void AdaptiveRefinement::record(std::span<const glm::vec4> colors) {
    if (colors.size() != pending_.size())
        throw std::invalid_argument("adaptive refinement: one colour per pending pixel");
    for (std::size_t i = 0; i < colors.size(); ++i) {
        colors_[pending_[i]] = colors[i];
        cast_[pending_[i]] = 1;
    }
    pixels_cast_ += colors.size();
    ++passes_;

    pending_.clear();
    tested_.clear();
    splitting_.clear();
    std::vector<Square> next;
    for (const Square& s : active_) {
        // A square no more than a pixel across has only its corners, all cast by now: nothing to fill.
        if (s.x1 - s.x0 < 2 && s.y1 - s.y0 < 2) continue;
        tested_.push_back(index(s.x0, s.y0));
        if (!needs_split(s)) {
            leaves_.push_back(s);
            continue;
        }
        splitting_.push_back(s);
        const int xm = s.x1 - s.x0 >= 2 ? (s.x0 + s.x1) / 2 : s.x0;
        const int ym = s.y1 - s.y0 >= 2 ? (s.y0 + s.y1) / 2 : s.y0;
        const std::pair<int, int> xr[2] = {{s.x0, xm == s.x0 ? s.x1 : xm}, {xm, s.x1}};
        const std::pair<int, int> yr[2] = {{s.y0, ym == s.y0 ? s.y1 : ym}, {ym, s.y1}};
        const int nx = xm == s.x0 ? 1 : 2;
        const int ny = ym == s.y0 ? 1 : 2;
        for (int j = 0; j < ny; ++j) {
            for (int i = 0; i < nx; ++i) {
                const Square child{xr[i].first, yr[j].first, xr[i].second, yr[j].second};
                next.push_back(child);
                for (const std::uint32_t p : {index(child.x0, child.y0), index(child.x1, child.y0),
                                              index(child.x0, child.y1), index(child.x1, child.y1)}) {
                    if (cast_[p] == 0) cast_[p] = 2;  // chosen for the next pass
                }
            }
        }
    }
    // The chosen pixels in row-major order, without sorting.
    for (std::uint32_t p = 0; p < cast_.size(); ++p) {
        if (cast_[p] == 2) {
            cast_[p] = 0;
            pending_.push_back(p);
        }
    }
    active_ = std::move(next);
}

Image AdaptiveRefinement::image() const {
    // The picture in bands of rows, in parallel. Each band copies its rows, then fills the parts of the
    // squares that lie in it, in the whole picture's order (the leaves, then the squares being split,
    // which show their corners' blend until their new corners are cast): a pixel on an edge two squares
    // share ends as one pass over all the squares would leave it.
    constexpr int kBandRows = 16;
    const int bands = (height_ + kBandRows - 1) / kBandRows;
    const auto all = static_cast<std::uint32_t>(leaves_.size() + splitting_.size());
    const auto square = [&](std::uint32_t i) -> const Square& {
        return i < leaves_.size() ? leaves_[i] : splitting_[i - leaves_.size()];
    };
    std::vector<std::vector<std::uint32_t>> in_band(static_cast<std::size_t>(bands));
    for (std::uint32_t i = 0; i < all; ++i)
        for (int b = square(i).y0 / kBandRows; b <= square(i).y1 / kBandRows; ++b)
            in_band[static_cast<std::size_t>(b)].push_back(i);
    Image out(width_, height_);
    pp5::parallel_for(0, bands, [&](int band) {
        const int top = band * kBandRows;
        const int bottom = std::min(height_, top + kBandRows) - 1;
        std::copy(colors_.begin() + index(0, top), colors_.begin() + index(0, bottom) + width_,
                  out.pixels.begin() + index(0, top));
        for (const std::uint32_t i : in_band[static_cast<std::size_t>(band)]) {
            const Square& s = square(i);
            const glm::vec4 c00 = colors_[index(s.x0, s.y0)];
            const glm::vec4 c10 = colors_[index(s.x1, s.y0)];
            const glm::vec4 c01 = colors_[index(s.x0, s.y1)];
            const glm::vec4 c11 = colors_[index(s.x1, s.y1)];
            const float w = static_cast<float>(std::max(1, s.x1 - s.x0));
            const float h = static_cast<float>(std::max(1, s.y1 - s.y0));
            for (int y = std::max(s.y0, top); y <= std::min(s.y1, bottom); ++y) {
                const float v = static_cast<float>(y - s.y0) / h;
                for (int x = s.x0; x <= s.x1; ++x) {
                    const std::uint32_t p = index(x, y);
                    if (cast_[p] != 0) continue;
                    const float u = static_cast<float>(x - s.x0) / w;
                    out.pixels[p] = (1.0f - v) * ((1.0f - u) * c00 + u * c10) + v * ((1.0f - u) * c01 + u * c11);
                }
            }
        }
    });
    return out;
}

}  // namespace pp5
