#include "kernels/wilson/slice_frame_builder.h"

#include "sim/core/parallel.h"

#include <algorithm>

namespace pp5::slicing {

void FrameBuilder::draw_regions() {
    frame.image = Image(width, height);
    frame.low_resolution = Image(width, height);
    std::vector<RegionTally> tallies(region_count);
    // Regions in parallel: each is drawn from its own lists.
    pp5::parallel_for(std::size_t{0}, region_count, [&](std::size_t r) {
        tallies[r] = draw_region(r, true, frame.image);
        draw_region(r, false, frame.low_resolution);
    });
    for (const RegionTally& t : tallies) {
        counts.quad_pixels += t.quad_pixels;
        counts.slice_composites += t.composites;
        counts.composited_pixels += t.composited_pixels;
        counts.point_pixels += t.point_pixels;
        counts.point_blocks += t.blocks;
        counts.block_pixels += t.block_pixels;
    }
}

FrameBuilder::RegionTally FrameBuilder::draw_region(std::size_t r, bool with_points, Image& out) const {
    const glm::ivec2 origin = region_origin(r);
    SliceRegion region(rc, rr);
    RegionTally tally;
    const std::vector<std::uint32_t>& rq = region_quads[r];
    const std::vector<std::uint32_t>& rp = region_points[r];
    std::size_t next_quad = 0, next_point = 0;
    std::vector<std::array<std::int32_t, 4>> block;  // the GPs' point blocks, reused across slabs
    for (std::uint32_t l = 0; l < layers.size(); ++l) {
        if (layers[l].kind == LayerKind::Plane) {
            if (next_quad < rq.size() && quads[rq[next_quad]].layer == l)
                next_quad = draw_slice(region, l, rq, next_quad, origin, tally);
            continue;
        }
        const std::size_t first = next_point;
        while (next_point < rp.size() && points[rp[next_point]].layer == l) ++next_point;
        if (with_points) draw_slab_points(region, rp, first, next_point, origin, tally, block);
    }
    write_pixels(region, origin, out);
    return tally;
}

std::size_t FrameBuilder::draw_slice(SliceRegion& region, std::uint32_t l, const std::vector<std::uint32_t>& list,
                                     std::size_t next, glm::ivec2 origin, RegionTally& tally) const {
    const int ox = origin.x, oy = origin.y;
    setup_slice(region, planes[static_cast<std::size_t>(layers[l].index)].setup(ox, oy));
    for (; next < list.size() && quads[list[next]].layer == l; ++next) {
        const Quad& q = quads[list[next]];
        QuadDraw draw;
        draw.key = SliceFormat::key(q.i + 1, q.j + 1);
        for (std::size_t ch = 0; ch < 4; ++ch) {
            const Quadratic local = q.channel[ch].shifted(ox, oy);
            draw.channels[ch] = to_qee(local.a, local.b, local.c, local.d, local.e, local.f, static_cast<double>(one));
        }
        draw.x0 = q.x0 - ox;
        draw.y0 = q.y0 - oy;
        draw.x1 = q.x1 - ox;
        draw.y1 = q.y1 - oy;
        tally.quad_pixels += draw_quad(region, draw, format_);
    }
    tally.composited_pixels += composite_slice(region, format_);
    ++tally.composites;
    return next;
}

void FrameBuilder::draw_slab_points(SliceRegion& region, const std::vector<std::uint32_t>& list, std::size_t first,
                                    std::size_t end, glm::ivec2 origin, RegionTally& tally,
                                    std::vector<std::array<std::int32_t, 4>>& block) const {
    const auto local = [&](const DrawnPoint& p) {
        PointSquare sq = p.square;
        sq.x0 -= origin.x;
        sq.x1 -= origin.x;
        sq.y0 -= origin.y;
        sq.y1 -= origin.y;
        return sq;
    };
    for (std::size_t e = first; e < end;) {
        if (!gp_sheets) {
            tally.point_pixels += draw_point_square(region, local(points[list[e]]), format_);
            ++e;
            continue;
        }
        // The (slab, brick)'s points in this region, composited by the GP into one block.
        std::size_t brick_end = e;
        int bx0 = rc, by0 = rr, bx1 = -1, by1 = -1;
        while (brick_end < end && points[list[brick_end]].brick == points[list[e]].brick) {
            const PointSquare sq = local(points[list[brick_end]]);
            bx0 = std::min(bx0, std::max(sq.x0, 0));
            by0 = std::min(by0, std::max(sq.y0, 0));
            bx1 = std::max(bx1, std::min(sq.x1, rc - 1));
            by1 = std::max(by1, std::min(sq.y1, rr - 1));
            ++brick_end;
        }
        block.assign(static_cast<std::size_t>(bx1 - bx0 + 1) * static_cast<std::size_t>(by1 - by0 + 1), {0, 0, 0, 0});
        for (std::size_t m = e; m < brick_end; ++m)
            tally.point_pixels += composite_point_into(block, bx0, by0, bx1, by1, local(points[list[m]]), format_);
        draw_block_over(region, bx0, by0, bx1, by1, block, format_);
        ++tally.blocks;
        tally.block_pixels += block.size();
        e = brick_end;
    }
}

void FrameBuilder::write_pixels(const SliceRegion& region, glm::ivec2 origin, Image& out) const {
    const float scale = 1.0f / static_cast<float>(one);
    for (int y = 0; y < rr && origin.y + y < height; ++y)
        for (int x = 0; x < rc && origin.x + x < width; ++x) {
            const std::size_t p = region.index(x, y);
            const float alpha = static_cast<float>(region.alpha[p]) * scale;
            glm::vec4 v;
            for (int ch = 0; ch < 3; ++ch)
                v[ch] = static_cast<float>(region.color[ch][p]) * scale + (1 - alpha) * background[ch];
            v.a = alpha;
            out.at(origin.x + x, origin.y + y) = v;
        }
}

}  // namespace pp5::slicing
