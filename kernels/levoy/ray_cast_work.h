#pragma once
// What Levoy's ray-casting phase records for the GPs (LevoyRenderer::cast_frame): the picture's
// tiles, each pass's rays in the order a GP casts them, and a task per tile and pass with an item per
// ray and a step per block the ray looks up.

#include "kernels/levoy/adaptive_refinement.h"
#include "kernels/levoy/ray_caster.h"
#include "sim/timing/recorded_work.h"

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace pp5 {

struct RayCastCounts;  // levoy_renderer.h

// The picture's square tiles, row-major: a GP task casts one tile's rays of one refinement pass.
struct ScreenTiles {
    int width = 0, height = 0, edge = 0;
    int across = 0, down = 0;

    ScreenTiles(int w, int h, int tile)
        : width(w), height(h), edge(tile), across((w + tile - 1) / tile), down((h + tile - 1) / tile) {}
    int count() const { return across * down; }
    int of(std::uint32_t pixel) const {
        const int x = static_cast<int>(pixel % static_cast<std::uint32_t>(width));
        const int y = static_cast<int>(pixel / static_cast<std::uint32_t>(width));
        return (y / edge) * across + x / edge;
    }
    ScreenRect rect(int t) const {
        const int x0 = (t % across) * edge, y0 = (t / across) * edge;
        return {static_cast<std::uint16_t>(x0), static_cast<std::uint16_t>(y0),
                static_cast<std::uint16_t>(std::min(width, x0 + edge) - x0),
                static_cast<std::uint16_t>(std::min(height, y0 + edge) - y0)};
    }
    std::uint32_t pixels_in(int t) const {
        const ScreenRect r = rect(t);
        return static_cast<std::uint32_t>(r.width) * r.height;
    }
};

// A pass's pending rays grouped by tile, row by row within a tile: the order a GP casts them in (a
// counting sort of the row-major pending list by tile keeps rows in order).
struct TileOrder {
    std::vector<std::uint32_t> first;   // per tile, its first ray in `pixels`; one more for the end
    std::vector<std::uint32_t> pixels;  // the rays in casting order
};

TileOrder order_by_tile(const ScreenTiles& tiles, const std::vector<std::uint32_t>& pending);

// The refinement decision's square tests, by the tile of each square's top-left corner.
std::vector<std::uint32_t> tests_per_tile(const ScreenTiles& tiles, const AdaptiveRefinement& refinement);

// Records the ray-casting phase as the GPs do it: a task per tile and pass, an item per ray, a step
// per block the ray looks up.
class RayWorkRecorder {
public:
    RayWorkRecorder(const ScreenTiles& tiles, bool interleave, GpPhase& job, RayCastCounts& counts)
        : tiles_(tiles), interleave_(interleave), job_(job), counts_(counts) {}

    // A pass's rays (cast in `order`), and a task per tile: its refinement tests (`tests`, per tile), an
    // item per ray, then the pixels it fills in (`filled`, per tile) and sends. The record is the one
    // that adding the tiles one by one in order would make; the tiles are recorded in parallel. Returns
    // the samples the pass's rays took.
    std::uint64_t add_pass(std::uint32_t pass, const CastBatch& batch, const TileOrder& order,
                           std::span<const std::uint32_t> tests, std::span<const std::uint32_t> filled);
    // Tile t's task of a pass: its refinement tests, the rays added since `first_item`, then the pixels
    // it fills in and sends. A task with nothing to do is left out.
    void add_task(std::uint32_t pass, int t, std::uint32_t first_item, std::uint32_t tests, std::uint32_t filled);

private:
    // A static assignment deals tile keys round-robin (key mod G). In raster order, a picture as many
    // tiles wide as there are GPs gives each GP one column, and the GPs' loads differ as the columns'
    // contents do. Skewing each row's keys by 7 (prime, so coprime to the usual power-of-two GP counts)
    // gives each GP tiles spread over rows and columns alike, and keys stay independent of the GP count.
    std::uint32_t key_of(int t) const {
        constexpr int kRowSkew = 7;
        return static_cast<std::uint32_t>(interleave_ ? t + kRowSkew * (t / tiles_.across) : t);
    }

    const ScreenTiles& tiles_;
    bool interleave_;
    GpPhase& job_;
    RayCastCounts& counts_;
};

}  // namespace pp5
