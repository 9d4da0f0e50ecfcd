#pragma once
// Levoy's adaptive refinement ("Volume rendering by adaptive refinement", 1989): cast a sparse grid of
// rays first, fill the other pixels by interpolation, then subdivide each square whose corner colours
// differ by more than a threshold and cast the new corners, pass after pass, until no square needs
// splitting or every square is a pixel wide.
//
// The first pass casts the pixels on a lattice of `initial_spacing` (with the image's last row and
// column added, so squares cover the whole image). A square splits at its midpoints along each side
// that is at least two pixels long. The picture after any pass shows the cast pixels as they are and
// fills every other pixel bilinearly from the corners of the square holding it. A negative threshold
// splits every square: the last pass then leaves no pixel uncast.

#include "scene/render/image.h"

#include <glm/vec4.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pp5 {

struct RefinementSettings {
    int initial_spacing = 8;  // pixels between the first pass's rays; >= 1
    float threshold = 0.1f;   // largest corner difference (any of r, g, b) left unsplit; < 0 splits all
};

class AdaptiveRefinement {
public:
    AdaptiveRefinement(int width, int height, RefinementSettings settings);

    int passes_recorded() const { return passes_; }
    bool finished() const { return pending_.empty(); }
    // The pixels the next pass casts (y * width + x, row-major order).
    const std::vector<std::uint32_t>& pending() const { return pending_; }
    // The squares tested to choose them, by their top-left pixel (none for the first pass).
    const std::vector<std::uint32_t>& tested_squares() const { return tested_; }

    // Takes the colours of pending() in order and chooses the next pass's pixels.
    void record(std::span<const glm::vec4> colors);

    // The picture so far: cast pixels and interpolated fill.
    Image image() const;
    bool cast(std::uint32_t pixel) const { return cast_[pixel] != 0; }
    std::uint64_t pixels_cast() const { return pixels_cast_; }

private:
    struct Square {
        int x0, y0, x1, y1;
    };
    std::uint32_t index(int x, int y) const {
        return static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(width_) + static_cast<std::uint32_t>(x);
    }
    bool needs_split(const Square& s) const;

    int width_;
    int height_;
    RefinementSettings settings_;
    int passes_ = 0;
    std::vector<glm::vec4> colors_;
    std::vector<std::uint8_t> cast_;
    std::uint64_t pixels_cast_ = 0;
    std::vector<Square> active_;     // squares whose corners are cast or pending, not yet split
    std::vector<Square> leaves_;     // squares that will never split and have pixels to fill
    std::vector<Square> splitting_;  // squares split by the last decision, shown whole until the next pass
    std::vector<std::uint32_t> pending_;
    std::vector<std::uint32_t> tested_;
};

}  // namespace pp5
