#include "kernels/yuan/splat_stages.h"

#include "kernels/yuan/splat_geometry.h"
#include "sim/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace pp5::splatting {

bool key_less(const Item& a, const Item& b) {
    if (a.band != b.band) return a.band < b.band;
    if (a.brick != b.brick) return a.brick < b.brick;
    if (a.depth != b.depth) return a.depth < b.depth;
    return a.voxel < b.voxel;
}

// Bricks in parallel, each into its own list, then joined in brick order.
void take_voxels(const FrameSetup& f, const ShadedCodes& voxels, std::vector<std::vector<std::uint32_t>>& brick_parts,
                 FrameBuffers& buffers) {
    const int edge = f.settings.brick_voxels;
    const auto bx = static_cast<std::size_t>(f.bricks.x), by = static_cast<std::size_t>(f.bricks.y);
    const std::size_t brick_count = bx * by * static_cast<std::size_t>(f.bricks.z);
    std::vector<std::vector<Item>>& per_brick = buffers.per_brick;
    per_brick.resize(brick_count);
    brick_parts.assign(brick_count, {});
    const auto kind_at = [&](const Item& item) {
        const double spacing_pixels = f.h * f.projection.pixels_per_unit(item.eye.z);
        if (f.projection.perspective() && item.eye.z <= f.kernel_world) return Kind::Culled;
        if (f.settings.primitives == PrimitiveMode::AllSplats) return Kind::Splat;
        if (f.settings.primitives == PrimitiveMode::AllPoints) return Kind::Point;
        return spacing_pixels > f.settings.switch_pixels ? Kind::Splat : Kind::Point;
    };
    pp5::parallel_for(std::size_t{0}, brick_count, [&](std::size_t b) {
        const glm::ivec3 bc(static_cast<int>(b % bx), static_cast<int>((b / bx) % by), static_cast<int>(b / (bx * by)));
        const glm::ivec3 lo = bc * edge;
        const glm::ivec3 hi = glm::min(lo + edge, f.dims);
        std::vector<std::uint32_t>& parts = brick_parts[b];
        per_brick[b].clear();
        parts.assign(static_cast<std::size_t>(f.machine.renderers), 0);
        for (int z = lo.z; z < hi.z; ++z)
            for (int y = lo.y; y < hi.y; ++y)
                for (int x = lo.x; x < hi.x; ++x) {
                    const std::size_t v = static_cast<std::size_t>(x) +
                                          static_cast<std::size_t>(f.dims.x) *
                                              (static_cast<std::size_t>(y) +
                                               static_cast<std::size_t>(f.dims.y) * static_cast<std::size_t>(z));
                    if (voxels.transparent(v)) continue;
                    Item item;
                    item.brick = static_cast<std::uint32_t>(b);
                    item.voxel = static_cast<std::uint32_t>(v);
                    item.eye = f.projection.to_eye(glm::vec3(x, y, z) * f.spacing);
                    item.depth = static_cast<float>(item.eye.z);
                    item.kind = kind_at(item);
                    per_brick[b].push_back(item);
                    ++parts[static_cast<std::size_t>(f.machine.renderer_of_voxel({x, y, z}))];
                }
    });
    std::vector<Item>& items = buffers.items;
    items.clear();
    for (const auto& v : per_brick) items.insert(items.end(), v.begin(), v.end());
}

// Bands are centred on the nearest voxel's depth, so that a layer of voxels at one depth (a slab face
// on) falls in the middle of a band, not on the rounding edge between two.
void order_by_band(const FrameSetup& f, std::vector<Item>& items) {
    float nearest = std::numeric_limits<float>::max();
    for (const Item& item : items) nearest = std::min(nearest, item.depth);
    const double band_depth = f.settings.band_voxels * f.h;
    for (Item& item : items)
        item.band = static_cast<std::uint32_t>(std::floor((item.depth - nearest) / band_depth + 0.5));
    pp5::parallel_sort(items.begin(), items.end(), key_less);
}

// In parallel: each primitive comes from its own voxel only, and every one is written once (a culled one
// as an empty primitive), so a buffer kept from the last frame needs no clearing.
void make_primitives(const FrameSetup& f, const ShadedCodes& voxels, std::vector<Item>& items,
                     std::vector<ScreenPrimitive>& primitives) {
    const double point_radius = f.settings.point_radius_pixels();
    primitives.resize(items.size());
    pp5::parallel_for(std::size_t{0}, items.size(), [&](std::size_t k) {
        Item& item = items[k];
        ScreenPrimitive& p = primitives[k];
        const glm::vec4 rgba = voxels.value(item.voxel);
        if (item.kind == Kind::Splat) {
            std::optional<ScreenPrimitive> splat = splat_primitive(f.projection, item.eye, f.kernel_world, rgba,
                                                                   f.tables, f.exact, f.format, f.width, f.height);
            if (!splat) item.kind = Kind::Culled;
            p = splat.value_or(ScreenPrimitive{});
        } else if (item.kind == Kind::Point) {
            p = point_primitive(f.projection, item.eye, f.h * f.projection.pixels_per_unit(item.eye.z), rgba,
                                point_radius, f.format, f.width, f.height);
        } else {
            p = ScreenPrimitive{};
        }
    });
}

RegionLists bin_by_region(const FrameSetup& f, const std::vector<Item>& items,
                          const std::vector<ScreenPrimitive>& primitives, SplatCounts& counts) {
    RegionLists lists(f.regions.count());
    for (std::size_t k = 0; k < items.size(); ++k) {
        const ScreenPrimitive& p = primitives[k];
        if (items[k].kind == Kind::Culled) {
            ++counts.culled;
            continue;
        }
        if (!p.visible()) {
            ++counts.offscreen;
            continue;
        }
        (items[k].kind == Kind::Splat ? counts.splats : counts.points) += 1;
        f.regions.for_each_under(p, [&](std::size_t region) {
            lists[region].push_back(RegionEntry{static_cast<std::uint32_t>(k), 0});
        });
    }
    return lists;
}

std::map<int, const PpTable*> footprint_rows(const FrameSetup& f, const std::vector<Item>& items,
                                             const std::vector<ScreenPrimitive>& primitives) {
    std::map<int, const PpTable*> rows;
    for (std::size_t k = 0; k < items.size(); ++k)
        if (items[k].kind == Kind::Splat && primitives[k].visible()) rows.emplace(primitives[k].row, nullptr);
    for (auto& [row, table] : rows) table = &f.tables.table(row);
    return rows;
}

}  // namespace pp5::splatting
