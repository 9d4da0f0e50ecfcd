#include "kernels/yuan/splat_stages.h"

#include "sim/core/parallel.h"

#include <algorithm>
#include <array>

namespace pp5::splatting {

namespace {

// One region drawn as its renderer draws it, from its own list only.
class RegionDrawer {
public:
    RegionDrawer(const FrameSetup& f, SplatBlend blend, const std::vector<Item>& items,
                 const std::vector<ScreenPrimitive>& primitives, const std::map<int, const PpTable*>& rows)
        : f_(f), blend_(blend), items_(items), primitives_(primitives), rows_(rows) {}

    RegionDrawn draw(std::size_t r, std::vector<RegionEntry>& list, glm::vec3 background, SplatFrame& frame) const {
        const glm::ivec2 origin = f_.regions.origin(r);
        RegionPixels region(f_.regions.columns, f_.regions.rows);
        std::vector<std::uint8_t> kinds(
            static_cast<std::size_t>(region.columns) * static_cast<std::size_t>(region.rows),
            0);  // bit 0 splat, 1 point
        RegionDrawn drawn;
        bool sheet_holds = false;
        std::uint32_t band = 0;
        const auto close_band = [&] {
            if (!sheet_holds) return;
            drawn.composited_pixels += composite_band(region, f_.format);
            drawn.bands.push_back(band);
            sheet_holds = false;
        };
        std::vector<std::array<std::int32_t, 4>> block;  // the GPs' sheet block, reused across chunks
        for (std::size_t e = 0; e < list.size();) {
            const Item& item = items_[list[e].item];
            if (item.band != band) {
                close_band();
                band = item.band;
            }
            if (item.kind == Kind::Splat) {
                draw_splat_entry(list[e], origin, region, kinds);
                if (blend_ == SplatBlend::Sheet) sheet_holds = true;
                ++e;
                continue;
            }
            sheet_holds = true;
            e = draw_points(list, e, origin, region, kinds, block);
        }
        close_band();
        write_pixels(origin, region, kinds, background, frame);
        return drawn;
    }

private:
    void mark(const ScreenPrimitive& p, glm::ivec2 origin, std::uint8_t bit, const RegionPixels& region,
              std::vector<std::uint8_t>& kinds) const {
        mark_box(p.x0 - origin.x, p.y0 - origin.y, p.x1 - origin.x, p.y1 - origin.y, bit, region, kinds);
    }
    static void mark_box(int x0, int y0, int x1, int y1, std::uint8_t bit, const RegionPixels& region,
                         std::vector<std::uint8_t>& kinds) {
        for (int y = std::max(y0, 0); y <= std::min(y1, region.rows - 1); ++y)
            for (int x = std::max(x0, 0); x <= std::min(x1, region.columns - 1); ++x) kinds[region.index(x, y)] |= bit;
    }

    void draw_splat_entry(RegionEntry& entry, glm::ivec2 origin, RegionPixels& region,
                          std::vector<std::uint8_t>& kinds) const {
        const ScreenPrimitive& p = primitives_[entry.item];
        const SplatDraw draw = splat_draw(p, origin.x, origin.y, f_.exact);
        const SplatIndexMode mode = f_.exact ? SplatIndexMode::Exact : SplatIndexMode::Affine;
        entry.pixels = draw_splat(region, draw, *rows_.at(p.row), f_.format, mode, blend_);
        mark(p, origin, 1, region, kinds);
    }

    // Points from entry `e`: on the renderers' path one is drawn; on the GPs' path the chunk's points in
    // this region are filtered into one block, which the renderer adds to its sheet. Returns the entry
    // after those drawn.
    std::size_t draw_points(std::vector<RegionEntry>& list, std::size_t e, glm::ivec2 origin, RegionPixels& region,
                            std::vector<std::uint8_t>& kinds, std::vector<std::array<std::int32_t, 4>>& block) const {
        const int rc = region.columns, rr = region.rows;
        if (f_.settings.point_path != PointPath::GpSheets) {
            const ScreenPrimitive& p = primitives_[list[e].item];
            list[e].pixels = draw_point(region, point_draw(p, origin.x, origin.y), f_.format);
            mark(p, origin, 2, region, kinds);
            return e + 1;
        }
        const Item& item = items_[list[e].item];
        std::size_t end = e;
        int bx0 = rc, by0 = rr, bx1 = -1, by1 = -1;
        while (end < list.size() && items_[list[end].item].band == item.band &&
               items_[list[end].item].brick == item.brick && items_[list[end].item].kind == Kind::Point) {
            const ScreenPrimitive& q = primitives_[list[end].item];
            bx0 = std::min(bx0, std::max(q.x0 - origin.x, 0));
            by0 = std::min(by0, std::max(q.y0 - origin.y, 0));
            bx1 = std::max(bx1, std::min(q.x1 - origin.x, rc - 1));
            by1 = std::max(by1, std::min(q.y1 - origin.y, rr - 1));
            ++end;
        }
        const int bw = bx1 - bx0 + 1;
        block.assign(static_cast<std::size_t>(bw) * static_cast<std::size_t>(by1 - by0 + 1), {0, 0, 0, 0});
        for (std::size_t k = e; k < end; ++k)
            list[k].pixels = filter_point(point_draw(primitives_[list[k].item], origin.x, origin.y), f_.format, bx0,
                                          by0, bx1, by1, block);
        add_sheet_block(region, bx0, by0, bx1, by1, block, f_.format);
        mark_box(bx0, by0, bx1, by1, 2, region, kinds);
        return end;
    }

    // The region's pixels: the volume over the background, and which kind of primitive drew each.
    void write_pixels(glm::ivec2 origin, const RegionPixels& region, const std::vector<std::uint8_t>& kinds,
                      glm::vec3 background, SplatFrame& frame) const {
        const float scale = 1.0f / static_cast<float>(f_.format.one());
        for (int y = 0; y < region.rows && origin.y + y < f_.height; ++y)
            for (int x = 0; x < region.columns && origin.x + x < f_.width; ++x) {
                const std::size_t p = region.index(x, y);
                const float a = static_cast<float>(region.alpha[p]) * scale;
                glm::vec4 out;
                for (int c = 0; c < 3; ++c)
                    out[c] = static_cast<float>(region.color[c][p]) * scale + (1 - a) * background[c];
                out.a = a;
                frame.image.at(origin.x + x, origin.y + y) = out;
                const std::uint8_t k = kinds[p];
                frame.primitive_map.at(origin.x + x, origin.y + y) = (k & 1)   ? glm::vec4(a, 0, 0, 1)
                                                                     : (k & 2) ? glm::vec4(a, a, a, 1)
                                                                               : glm::vec4(0, 0, 0, 1);
            }
    }

    const FrameSetup& f_;
    SplatBlend blend_;
    const std::vector<Item>& items_;
    const std::vector<ScreenPrimitive>& primitives_;
    const std::map<int, const PpTable*>& rows_;
};

}  // namespace

std::vector<RegionDrawn> draw_regions(const FrameSetup& f, SplatBlend blend, const std::vector<Item>& items,
                                      const std::vector<ScreenPrimitive>& primitives,
                                      const std::map<int, const PpTable*>& rows, RegionLists& lists,
                                      glm::vec3 background, SplatFrame& frame) {
    frame.image = Image(f.width, f.height);
    frame.primitive_map = Image(f.width, f.height);
    std::vector<RegionDrawn> drawn(f.regions.count());
    const RegionDrawer drawer(f, blend, items, primitives, rows);
    pp5::parallel_for(std::size_t{0}, f.regions.count(),
                      [&](std::size_t r) { drawn[r] = drawer.draw(r, lists[r], background, frame); });
    return drawn;
}

}  // namespace pp5::splatting
