#pragma once
// Internal to the reference renderer: trilinear interpolation on the voxel grid, x fastest.

#include <glm/common.hpp>
#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace pp5::detail {

// The cell around a position and the position's place inside it. Positions are clamped to the grid
// (the boundary rule for interpolation); the cell's lower corner stops at dims-2 so that the upper
// face is reached with weight 1. Requires every dimension >= 2.
struct Cell {
    glm::ivec3 corner{0};    // the lower corner voxel
    std::size_t base = 0;    // its index
    glm::vec3 weight{0.0f};  // fractional position in the cell, in [0,1]
};

class Grid {
public:
    explicit Grid(glm::ivec3 dims)
        : last_cell_(dims - 2),
          upper_(glm::vec3(dims - 1)),
          row_(static_cast<std::size_t>(dims.x)),
          slice_(static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y)) {}

    Cell cell(glm::vec3 position) const {
        const glm::vec3 p = glm::clamp(position, glm::vec3(0.0f), upper_);
        const glm::ivec3 corner = glm::min(glm::ivec3(p), last_cell_);  // p >= 0: truncation is floor
        Cell c;
        c.corner = corner;
        c.base = static_cast<std::size_t>(corner.x) + row_ * static_cast<std::size_t>(corner.y) +
                 slice_ * static_cast<std::size_t>(corner.z);
        c.weight = p - glm::vec3(corner);
        return c;
    }

    // Interpolates colour and opacity together. The same arithmetic as interpolate<glm::vec4>, lane by
    // lane (a + (b - a) t, in the same order), four lanes at a time where SSE is available.
    glm::vec4 interpolate_rgba(const Cell& c, const glm::vec4* rgba) const {
#if defined(__SSE2__)
        return blend(c, [&](std::size_t voxel) {
            const float* v = &rgba[voxel].x;
            return std::pair{_mm_loadu_ps(v), _mm_loadu_ps(v + 4)};
        });
#else
        return interpolate<glm::vec4>(c, [&](std::size_t i) { return rgba[i]; });
#endif
    }

    // The same for a voxel's four codes of 8 or 16 bits, each decoded as code / code_max before
    // interpolating: the result interpolate_rgba gives over a volume of decoded floats, without
    // storing one.
    template <class Code>
    glm::vec4 interpolate_codes(const Cell& c, const Code* codes, glm::vec4 code_max) const {
#if defined(__SSE2__)
        const __m128 scale = _mm_loadu_ps(&code_max.x);
        const __m128i zero = _mm_setzero_si128();
        return blend(c, [&](std::size_t voxel) {
            // One load holds a voxel and its x neighbour, widened to 16 bits a channel.
            const auto* p = &codes[voxel].x;
            __m128i both;
            if constexpr (sizeof(*p) == 1)
                both = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)), zero);
            else both = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
            return std::pair{_mm_div_ps(_mm_cvtepi32_ps(_mm_unpacklo_epi16(both, zero)), scale),
                             _mm_div_ps(_mm_cvtepi32_ps(_mm_unpackhi_epi16(both, zero)), scale)};
        });
#else
        return interpolate<glm::vec4>(c, [&](std::size_t i) { return glm::vec4(codes[i]) / code_max; });
#endif
    }

    // Interpolates any type with + and * float, read by index.
    template <class T, class Read>
    T interpolate(const Cell& c, Read&& read) const {
        const glm::vec3 w = c.weight;
        const std::size_t i = c.base;
        const T x00 = lerp(read(i), read(i + 1), w.x);
        const T x10 = lerp(read(i + row_), read(i + row_ + 1), w.x);
        const T x01 = lerp(read(i + slice_), read(i + slice_ + 1), w.x);
        const T x11 = lerp(read(i + slice_ + row_), read(i + slice_ + row_ + 1), w.x);
        return lerp(lerp(x00, x10, w.y), lerp(x01, x11, w.y), w.z);
    }

private:
#if defined(__SSE2__)
    static __m128 lerp4(__m128 a, __m128 b, __m128 t) { return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), t)); }
    // The cell's trilinear blend, four lanes at a time, in interpolate's order: `corners(voxel)` gives a
    // voxel's four channels and its x neighbour's.
    template <class Corners>
    glm::vec4 blend(const Cell& c, Corners&& corners) const {
        const __m128 wx = _mm_set1_ps(c.weight.x);
        const auto along_x = [&](std::size_t voxel) {
            const auto [low, high] = corners(voxel);
            return lerp4(low, high, wx);
        };
        const __m128 x00 = along_x(c.base);
        const __m128 x10 = along_x(c.base + row_);
        const __m128 x01 = along_x(c.base + slice_);
        const __m128 x11 = along_x(c.base + slice_ + row_);
        const __m128 wy = _mm_set1_ps(c.weight.y);
        const __m128 result = lerp4(lerp4(x00, x10, wy), lerp4(x01, x11, wy), _mm_set1_ps(c.weight.z));
        glm::vec4 out;
        _mm_storeu_ps(&out.x, result);
        return out;
    }
#endif
    template <class T>
    static T lerp(const T& a, const T& b, float t) {
        return a + (b - a) * t;
    }

    glm::ivec3 last_cell_;
    glm::vec3 upper_;
    std::size_t row_;
    std::size_t slice_;
};

}  // namespace pp5::detail
