#pragma once
// The stages of one frame of hybrid splatting (HybridSplatter::render), and what they hand each other:
// the voxels taken, ordered, made primitives and binned (splat_stages.cpp), each region drawn as its
// renderer draws it (region_drawing.cpp), and the machine's work recorded (splat_work.cpp).

#include "kernels/yuan/hybrid_splatter.h"
#include "kernels/yuan/screen_primitives.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <map>
#include <vector>

namespace pp5::splatting {

enum class Kind : std::uint8_t { Splat, Point, Culled };

// A non-transparent voxel on its way to the screen.
struct Item {
    std::uint32_t band = 0;
    std::uint32_t brick = 0;
    float depth = 0;
    std::uint32_t voxel = 0;  // linear index (the last tie-break, so the order is total)
    Kind kind = Kind::Point;
    glm::dvec3 eye{0};
};

// The order every renderer takes: (band, brick, depth), then the voxel, so that the order is total.
bool key_less(const Item& a, const Item& b);

// A primitive's place in one region's list, and the pixels it changed there.
struct RegionEntry {
    std::uint32_t item = 0;
    std::uint32_t pixels = 0;
};
using RegionLists = std::vector<std::vector<RegionEntry>>;

// The picture's 128x128 screen regions, row-major; each is drawn by renderer (index mod renderers).
struct ScreenRegions {
    int columns = 0, rows = 0;  // pixels a region
    int across = 0, down = 0;
    std::size_t count() const { return static_cast<std::size_t>(across) * static_cast<std::size_t>(down); }
    std::size_t index(int rx, int ry) const {
        return static_cast<std::size_t>(ry) * static_cast<std::size_t>(across) + static_cast<std::size_t>(rx);
    }
    glm::ivec2 origin(std::size_t r) const {
        return {static_cast<int>(r % static_cast<std::size_t>(across)) * columns,
                static_cast<int>(r / static_cast<std::size_t>(across)) * rows};
    }
    // Every region a primitive's screen box touches, in row-major order.
    template <typename Visit>
    void for_each_under(const ScreenPrimitive& p, Visit&& visit) const {
        for (int ry = p.y0 / rows; ry <= p.y1 / rows; ++ry)
            for (int rx = p.x0 / columns; rx <= p.x1 / columns; ++rx) visit(index(rx, ry));
    }
};

// What one frame's stages share: the splatter's settings and machine, and the view.
struct FrameSetup {
    const YuanSettings& settings;
    const RegionMachine& machine;
    glm::ivec3 dims;
    glm::vec3 spacing;
    glm::ivec3 bricks;
    const RegionFormat& format;
    ScreenProjection projection;
    int width = 0, height = 0;
    double h = 0;             // the finest voxel spacing
    double kernel_world = 0;  // the splat kernel's radius in world units
    bool exact = false;       // the exact footprint index (perspective views only)
    const FootprintTables& tables;
    ScreenRegions regions;

    std::size_t renderer_of_region(std::size_t region) const {
        return region % static_cast<std::size_t>(machine.renderers);
    }
};

// The per-voxel arrays of a frame, kept by the splatter for the next one: a frame of the MR head holds
// a million items and 250 MB of primitives, and memory allocated afresh each frame is memory the host
// must fault in again.
struct FrameBuffers {
    std::vector<std::vector<Item>> per_brick;
    std::vector<Item> items;
    std::vector<ScreenPrimitive> primitives;
};

// 1. The non-transparent voxels of each brick into `buffers.items`, transformed and split (bricks in
// parallel, then in order); `brick_parts` gets, per brick and renderer, the voxels that renderer streams.
void take_voxels(const FrameSetup& f, const ShadedCodes& voxels, std::vector<std::vector<std::uint32_t>>& brick_parts,
                 FrameBuffers& buffers);
// 2. Bands by depth, then the renderers' order (key_less).
void order_by_band(const FrameSetup& f, std::vector<Item>& items);
// 3. Each item's primitive into `primitives`; a splat whose kernel reaches the eye's plane is culled.
void make_primitives(const FrameSetup& f, const ShadedCodes& voxels, std::vector<Item>& items,
                     std::vector<ScreenPrimitive>& primitives);
// 4. Each region's primitives in the renderers' order, with the counts of what was drawn, culled or
// fell outside the picture.
RegionLists bin_by_region(const FrameSetup& f, const std::vector<Item>& items,
                          const std::vector<ScreenPrimitive>& primitives, SplatCounts& counts);
// The footprint rows the visible splats use, made once rather than looked up under a lock per draw.
std::map<int, const PpTable*> footprint_rows(const FrameSetup& f, const std::vector<Item>& items,
                                             const std::vector<ScreenPrimitive>& primitives);

// What drawing a region left for the machine's account: the bands whose sheets it composited and the
// pixels those composites changed.
struct RegionDrawn {
    std::vector<std::uint32_t> bands;
    std::uint64_t composited_pixels = 0;
};

// 5. Every region drawn as its renderer draws it (regions in parallel: each from its own list), into
// the frame's picture and primitive map; each list entry gets the pixels its primitive changed.
std::vector<RegionDrawn> draw_regions(const FrameSetup& f, SplatBlend blend, const std::vector<Item>& items,
                                      const std::vector<ScreenPrimitive>& primitives,
                                      const std::map<int, const PpTable*>& rows, RegionLists& lists,
                                      glm::vec3 background, SplatFrame& frame);

// 6. The machine's work (frame.work): one GP task per (band, brick) chunk, batches to the renderers,
// their steps, each region's readout, and what a lone processor would do instead of the renderers.
void record_work(const FrameSetup& f, const RegionPrograms& programs, const std::map<int, const PpTable*>& rows,
                 const std::vector<Item>& items, const std::vector<ScreenPrimitive>& primitives, RegionLists& lists,
                 const std::vector<RegionDrawn>& drawn, const std::vector<std::vector<std::uint32_t>>& brick_parts,
                 SplatFrame& frame);

}  // namespace pp5::splatting
