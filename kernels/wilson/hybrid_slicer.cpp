#include "kernels/wilson/hybrid_slicer.h"

#include "kernels/shared/screen_regions/screen_projection.h"
#include "kernels/wilson/slice_geometry.h"
#include "kernels/wilson/wilson_costs.h"
#include "sim/core/parallel.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

namespace {

constexpr std::uint32_t kUnitBits = 48;         // a texel as the renderers stream it: RGBA and its place in the brick
constexpr std::uint32_t kCachedTexelBits = 64;  // and as a GP keeps it
constexpr std::uint64_t kHeaderBits = 64;       // a batch's header: kind, layer, brick, count
constexpr std::uint64_t kCoefficientBits = 32;
constexpr std::uint64_t kConstantBits = 16;
// A quad: its key and four channels of six coefficients. A point: two span tests of three coefficients
// and four constants. A slice setup per region: three linear functions.
constexpr std::uint64_t kQuadBits = kConstantBits * 2 + 4 * 6 * kCoefficientBits;
constexpr std::uint64_t kPointBits = 2 * 3 * kCoefficientBits + 4 * kConstantBits;
constexpr std::uint64_t kSetupBits = 3 * 3 * kCoefficientBits;
constexpr std::uint64_t kQuadCoefficients = 4 * 6 + 1;
constexpr std::uint64_t kPointCoefficients = 2 * 3 + 4;

enum class LayerKind { Plane, Slab };
struct Layer {
    LayerKind kind = LayerKind::Plane;
    int index = 0;  // the plane, or the slab's lower plane (-1 below the first)
};

// A texel cell drawn this frame.
struct Quad {
    std::uint32_t layer = 0;
    std::uint32_t brick = 0;
    std::int32_t i = 0, j = 0;
    std::array<Quadratic, 4> channel;  // red, green, blue, opacity in [0, 1], of the screen position
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

// A stored point as this frame draws it.
struct DrawnPoint {
    std::uint32_t layer = 0;
    std::uint32_t brick = 0;
    std::uint32_t index = 0;  // storage order
    bool drawn = false;
    bool offscreen = false;
    int side = 0;
    PointSquare square;  // screen pixels
};

std::size_t linear(glm::ivec3 d, glm::ivec3 p) {
    return static_cast<std::size_t>(p.x) +
           static_cast<std::size_t>(d.x) *
               (static_cast<std::size_t>(p.y) + static_cast<std::size_t>(d.y) * static_cast<std::size_t>(p.z));
}

// Over a region, what a layer asks: which regions each primitive reaches, row-major region indices.
template <class Visit>
void for_each_region(int x0, int y0, int x1, int y1, int rc, int rr, int regions_x, Visit&& visit) {
    for (int ry = y0 / rr; ry <= y1 / rr; ++ry)
        for (int rx = x0 / rc; rx <= x1 / rc; ++rx)
            visit(static_cast<std::size_t>(ry) * static_cast<std::size_t>(regions_x) + static_cast<std::size_t>(rx));
}

// One frame's construction: the layers, the quads and points, each region drawn by its twins, and the
// recorded work. Each step reads what the steps before it left.
class FrameBuilder {
public:
    FrameBuilder(const HybridSlicer& slicer, const WilsonSettings& settings, const RegionMachine& machine,
                 const HybridVolume& hybrid, glm::vec3 spacing, glm::ivec3 bricks, const SliceFormat& format,
                 const SlicePrograms& programs, const ShadedCodes& shaded_texels, const PointLook& point_look,
                 const Camera& view, int image_width, int image_height, glm::vec3 image_background)
        : slicer_(slicer),
          settings_(settings),
          machine_(machine),
          hybrid_(&hybrid),
          spacing_(spacing),
          bricks_(bricks),
          format_(format),
          programs_(programs),
          texels(shaded_texels),
          look(point_look),
          camera(view),
          width(image_width),
          height(image_height),
          background(image_background),
          projection(view, image_width, image_height),
          low(hybrid.low_resolution()),
          n(low.dims()),
          k(hybrid.factor()),
          stack(choose_slices(view_direction(hybrid, spacing, view, projection))),
          a(stack.axis),
          b((a + 1) % 3),
          c((a + 2) % 3),
          min_spacing(std::min({spacing.x, spacing.y, spacing.z})),
          one(format.one()),
          edge(settings.brick_voxels),
          rc(machine.region_columns),
          rr(machine.region_rows),
          regions_x((image_width + rc - 1) / rc),
          regions_y((image_height + rr - 1) / rr),
          region_count(static_cast<std::size_t>(regions_x) * static_cast<std::size_t>(regions_y)),
          gp_sheets(settings.point_path == WilsonPointPath::GpSheets) {
        counts.slice_axis = a;
    }

    HybridFrame build() {
        make_layers();
        make_quads();
        make_points();
        bin_by_region();
        draw_regions();
        record_work();
        return std::move(frame);
    }

private:
    // Eye to the volume's centre under perspective, else the camera's forward.
    static glm::vec3 view_direction(const HybridVolume& hybrid, glm::vec3 spacing, const Camera& camera,
                                    const ScreenProjection& projection) {
        const glm::vec3 center = glm::vec3(hybrid.error_grid() / hybrid.error_grid_factor() - 1) * spacing * 0.5f;
        return projection.perspective() ? center - camera.eye : camera.forward();
    }

    // The distance a ray travels between two slices, in the voxels opacity is measured per.
    double path_voxels(glm::dvec3 world, double thickness) const {
        const glm::dvec3 d = projection.perspective() ? world - glm::dvec3(camera.eye) : glm::dvec3(camera.forward());
        const double cosine = std::abs(d[a]) / glm::length(d);
        return thickness * spacing_[a] / (std::max(cosine, 1e-6) * min_spacing);
    }

    std::uint32_t brick_at(glm::ivec3 texel) const {
        const glm::ivec3 bc = texel / edge;
        return static_cast<std::uint32_t>(bc.x + bricks_.x * (bc.y + bricks_.y * bc.z));
    }
    std::uint32_t brick_of(const HybridPoint& point) const { return slicer_.brick_of(point); }

    // The layers, back to front.
    void make_layers() {
        if (stack.far_is_high) {
            for (int s = n[a] - 1; s >= 0; --s) {
                layers.push_back({LayerKind::Slab, s});
                layers.push_back({LayerKind::Plane, s});
            }
            layers.push_back({LayerKind::Slab, -1});
        } else {
            layers.push_back({LayerKind::Slab, -1});
            for (int s = 0; s < n[a]; ++s) {
                layers.push_back({LayerKind::Plane, s});
                layers.push_back({LayerKind::Slab, s});
            }
        }
        plane_layer.assign(static_cast<std::size_t>(n[a]), 0);
        slab_layer.assign(static_cast<std::size_t>(n[a]) + 1, 0);
        for (std::size_t l = 0; l < layers.size(); ++l)
            (layers[l].kind == LayerKind::Plane ? plane_layer[static_cast<std::size_t>(layers[l].index)]
                                                : slab_layer[static_cast<std::size_t>(layers[l].index + 1)]) =
                static_cast<std::uint32_t>(l);
        for (int s = 0; s < n[a]; ++s) planes.emplace_back(projection, a, s, spacing_, k);
    }

    // Each plane's quads, brick by brick (planes in parallel).
    void make_quads() {
        plane_quads.assign(static_cast<std::size_t>(n[a]), {});
        plane_counts.assign(static_cast<std::size_t>(n[a]), {});
        pp5::parallel_for(0, n[a], [&](int s) {
            const SlicePlane& plane = planes[static_cast<std::size_t>(s)];
            HybridCounts& pc = plane_counts[static_cast<std::size_t>(s)];
            // The plane's texels with their opacity corrected.
            std::vector<glm::vec4> texel(static_cast<std::size_t>(n[b]) * static_cast<std::size_t>(n[c]));
            for (int j = 0; j < n[c]; ++j)
                for (int i = 0; i < n[b]; ++i) {
                    glm::ivec3 p;
                    p[a] = s;
                    p[b] = i;
                    p[c] = j;
                    glm::vec4 v = texels.value(linear(n, p));
                    if (settings_.opacity_correction == SliceOpacityCorrection::PerSlice && v.a > 0)
                        v.a = static_cast<float>(
                            1.0 - std::pow(1.0 - std::min<double>(v.a, 1.0), path_voxels(plane.world(i, j), k)));
                    texel[static_cast<std::size_t>(i) + static_cast<std::size_t>(n[b]) * static_cast<std::size_t>(j)] =
                        v;
                }
            const auto at = [&](int i, int j) {
                return texel[static_cast<std::size_t>(i) +
                             static_cast<std::size_t>(n[b]) * static_cast<std::size_t>(j)];
            };
            // Bricks in order, cells in order within each.
            glm::ivec3 brick_lo(0);
            brick_lo[a] = s / edge * edge;
            for (int bj = 0; bj < n[c]; bj += edge)
                for (int bi = 0; bi < n[b]; bi += edge) {
                    brick_lo[b] = bi;
                    brick_lo[c] = bj;
                    const std::uint32_t brick = brick_at(brick_lo);
                    for (int j = bj; j < std::min(bj + edge, n[c] - 1); ++j)
                        for (int i = bi; i < std::min(bi + edge, n[b] - 1); ++i) {
                            ++pc.cells;
                            const glm::vec4 corner[2][2] = {{at(i, j), at(i, j + 1)}, {at(i + 1, j), at(i + 1, j + 1)}};
                            if (!(corner[0][0].a > 0 || corner[0][1].a > 0 || corner[1][0].a > 0 || corner[1][1].a > 0))
                                continue;
                            // Its screen box from the cell's corners.
                            glm::dvec2 lo(1e300), hi(-1e300);
                            bool behind = false;
                            for (int dj = 0; dj < 2; ++dj)
                                for (int di = 0; di < 2; ++di) {
                                    const glm::dvec3 e = projection.to_eye(glm::vec3(plane.world(i + di, j + dj)));
                                    if (projection.perspective() && e.z <= 1e-6 * min_spacing) behind = true;
                                    const glm::dvec2 sp = projection.to_screen(e);
                                    lo = glm::min(lo, sp);
                                    hi = glm::max(hi, sp);
                                }
                            if (behind) {
                                ++pc.cells_behind_eye;
                                continue;
                            }
                            Quad q;
                            q.layer = plane_layer[static_cast<std::size_t>(s)];
                            q.brick = brick;
                            q.i = i;
                            q.j = j;
                            q.x0 = std::max(0, static_cast<int>(std::floor(lo.x)) - 1);
                            q.y0 = std::max(0, static_cast<int>(std::floor(lo.y)) - 1);
                            q.x1 = std::min(width - 1, static_cast<int>(std::ceil(hi.x)) + 1);
                            q.y1 = std::min(height - 1, static_cast<int>(std::ceil(hi.y)) + 1);
                            if (q.x1 < q.x0 || q.y1 < q.y0) {
                                ++pc.quads_offscreen;
                                continue;
                            }
                            const glm::dvec2 middle =
                                projection.to_screen(projection.to_eye(glm::vec3(plane.world(i + 0.5, j + 0.5))));
                            for (int ch = 0; ch < 4; ++ch) {
                                const std::array<std::array<double, 2>, 2> f = {
                                    {{corner[0][0][ch], corner[0][1][ch]}, {corner[1][0][ch], corner[1][1][ch]}}};
                                q.channel[static_cast<std::size_t>(ch)] = cell_quadratic(plane, i, j, f, middle);
                            }
                            plane_quads[static_cast<std::size_t>(s)].push_back(q);
                        }
                }
        });
    }

    // The points: shaded, corrected and sized (in parallel), then in (layer, brick, storage) order; then all quads in
    // layer order.
    void make_points() {
        const std::span<const HybridPoint> stored = hybrid_->points();
        points.resize(stored.size());
        const double grid_spacing = 1.0 / hybrid_->error_grid_factor();
        const double point_world = std::max({spacing_.x, spacing_.y, spacing_.z}) * grid_spacing;
        const NormalTable& normals = NormalTable::get();
        pp5::parallel_for(std::size_t{0}, stored.size(), [&](std::size_t m) {
            const HybridPoint& hp = stored[m];
            DrawnPoint& p = points[m];
            p.index = static_cast<std::uint32_t>(m);
            const glm::vec3 position = hybrid_->position(hp);
            p.brick = brick_of(hp);
            const double along = (position[a] + 0.5) / k - 0.5;
            const int slab = std::clamp(static_cast<int>(std::floor(along)), -1, n[a] - 1);
            p.layer = slab_layer[static_cast<std::size_t>(slab + 1)];
            const glm::vec3 world = position * spacing_;
            const glm::dvec3 eye = projection.to_eye(world);
            if (projection.perspective() && eye.z <= point_world) {
                p.offscreen = true;
                return;
            }
            // What the point must add over the low-resolution volume's opacity there.
            const float value = hybrid_->value(hp), low_value = value - hybrid_->error(hp);
            const float gradient = hybrid_->gradient_magnitude(hp);
            const double path = path_voxels(glm::dvec3(world), grid_spacing);
            const auto over_cell = [&](float v) {
                return 1.0 - std::pow(1.0 - std::min(1.0f, look.classification->opacity(v, gradient)), path);
            };
            const double full = over_cell(value), partial = over_cell(low_value);
            double added = partial < 1.0 ? std::max(0.0, (full - partial) / (1.0 - partial)) : 0.0;
            added = std::min(1.0, added * settings_.point_opacity_scale);
            // Its square: the projected error-grid spacing, rounded up, the opacity scaled down by the area gained.
            const double sigma = point_world * projection.pixels_per_unit(eye.z) * settings_.point_overlap;
            const int side = std::max(1, static_cast<int>(std::ceil(sigma)));
            const double alpha = std::min(1.0, added * sigma * sigma / (static_cast<double>(side) * side));
            const glm::vec3 to_viewer = look.view.to_viewer(world);
            const glm::vec3 to_light =
                look.lighting.light_follows_camera ? to_viewer : glm::normalize(look.lighting.light_direction);
            const glm::vec3 color =
                glm::clamp(phong_shade(look.lighting, look.colors->color(value), normals.direction(hp.normal), to_light,
                                       to_viewer, look.view.depth(world)),
                           glm::vec3(0.0f), glm::vec3(1.0f));
            const std::int64_t premultiplied_alpha =
                std::min<std::int64_t>(std::llround(alpha * static_cast<double>(one)), format_.top());
            p.side = side;
            if (premultiplied_alpha == 0) return;
            const glm::dvec2 sp = projection.to_screen(eye);
            PointSquare& sq = p.square;
            sq.x0 = static_cast<int>(std::ceil(sp.x - side / 2.0));
            sq.y0 = static_cast<int>(std::ceil(sp.y - side / 2.0));
            sq.x1 = sq.x0 + side - 1;
            sq.y1 = sq.y0 + side - 1;
            for (int ch = 0; ch < 3; ++ch)
                sq.premultiplied[static_cast<std::size_t>(ch)] = std::min<std::int64_t>(
                    std::llround(alpha * static_cast<double>(color[ch]) * static_cast<double>(one)),
                    premultiplied_alpha);
            sq.premultiplied[3] = premultiplied_alpha;
            sq.x0 = std::max(sq.x0, 0);
            sq.y0 = std::max(sq.y0, 0);
            sq.x1 = std::min(sq.x1, width - 1);
            sq.y1 = std::min(sq.y1, height - 1);
            if (sq.x1 < sq.x0 || sq.y1 < sq.y0) p.offscreen = true;
            else p.drawn = true;
        });
        std::stable_sort(points.begin(), points.end(), [](const DrawnPoint& x, const DrawnPoint& y) {
            return x.layer != y.layer ? x.layer < y.layer : x.brick < y.brick;
        });
        counts.points = points.size();
        for (const DrawnPoint& p : points) {
            if (p.offscreen) ++counts.points_offscreen;
            else if (!p.drawn) ++counts.points_transparent;
            else {
                ++counts.points_drawn;
                ++counts.point_sizes[p.side];
            }
        }

        // All quads in layer order.
        first_quad_of_layer.assign(layers.size() + 1, 0);
        for (std::size_t l = 0; l < layers.size(); ++l) {
            first_quad_of_layer[l] = quads.size();
            if (layers[l].kind == LayerKind::Plane) {
                auto& v = plane_quads[static_cast<std::size_t>(layers[l].index)];
                quads.insert(quads.end(), v.begin(), v.end());
                v = {};
            }
        }
        first_quad_of_layer[layers.size()] = quads.size();
        for (const HybridCounts& pc : plane_counts) {
            counts.cells += pc.cells;
            counts.cells_behind_eye += pc.cells_behind_eye;
            counts.quads_offscreen += pc.quads_offscreen;
        }
        counts.quads = quads.size();
    }

    // Regions and their lists (in layer order, as the primitives are).
    void bin_by_region() {
        region_quads.resize(region_count);
        region_points.resize(region_count);
        for (std::size_t q = 0; q < quads.size(); ++q)
            for_each_region(quads[q].x0, quads[q].y0, quads[q].x1, quads[q].y1, rc, rr, regions_x,
                            [&](std::size_t r) { region_quads[r].push_back(static_cast<std::uint32_t>(q)); });
        for (std::size_t m = 0; m < points.size(); ++m)
            if (points[m].drawn)
                for_each_region(points[m].square.x0, points[m].square.y0, points[m].square.x1, points[m].square.y1, rc,
                                rr, regions_x,
                                [&](std::size_t r) { region_points[r].push_back(static_cast<std::uint32_t>(m)); });
    }

    // Every region drawn as its renderer draws it, with and without the points.
    void draw_regions() {
        frame.image = Image(width, height);
        frame.low_resolution = Image(width, height);
        struct RegionTally {
            std::uint64_t quad_pixels = 0, composites = 0, composited_pixels = 0, point_pixels = 0, blocks = 0,
                          block_pixels = 0;
        };
        std::vector<RegionTally> tallies(region_count);
        pp5::parallel_for(std::size_t{0}, region_count, [&](std::size_t r) {
            const int ox = static_cast<int>(r % static_cast<std::size_t>(regions_x)) * rc;
            const int oy = static_cast<int>(r / static_cast<std::size_t>(regions_x)) * rr;
            for (const bool with_points : {true, false}) {
                SliceRegion region(rc, rr);
                RegionTally tally;
                const std::vector<std::uint32_t>& rq = region_quads[r];
                const std::vector<std::uint32_t>& rp = region_points[r];
                std::size_t next_quad = 0, next_point = 0;
                std::vector<std::array<std::int32_t, 4>> block;
                for (std::uint32_t l = 0; l < layers.size(); ++l) {
                    if (layers[l].kind == LayerKind::Plane) {
                        if (next_quad >= rq.size() || quads[rq[next_quad]].layer != l) continue;
                        setup_slice(region, planes[static_cast<std::size_t>(layers[l].index)].setup(ox, oy));
                        for (; next_quad < rq.size() && quads[rq[next_quad]].layer == l; ++next_quad) {
                            const Quad& q = quads[rq[next_quad]];
                            QuadDraw draw;
                            draw.key = SliceFormat::key(q.i + 1, q.j + 1);
                            for (std::size_t ch = 0; ch < 4; ++ch) {
                                const Quadratic local = q.channel[ch].shifted(ox, oy);
                                draw.channels[ch] = to_qee(local.a, local.b, local.c, local.d, local.e, local.f,
                                                           static_cast<double>(one));
                            }
                            draw.x0 = q.x0 - ox;
                            draw.y0 = q.y0 - oy;
                            draw.x1 = q.x1 - ox;
                            draw.y1 = q.y1 - oy;
                            tally.quad_pixels += draw_quad(region, draw, format_);
                        }
                        tally.composited_pixels += composite_slice(region, format_);
                        ++tally.composites;
                        continue;
                    }
                    const std::size_t first = next_point;
                    while (next_point < rp.size() && points[rp[next_point]].layer == l) ++next_point;
                    if (!with_points) continue;
                    for (std::size_t e = first; e < next_point;) {
                        const auto local = [&](const DrawnPoint& p) {
                            PointSquare sq = p.square;
                            sq.x0 -= ox;
                            sq.x1 -= ox;
                            sq.y0 -= oy;
                            sq.y1 -= oy;
                            return sq;
                        };
                        if (!gp_sheets) {
                            tally.point_pixels += draw_point_square(region, local(points[rp[e]]), format_);
                            ++e;
                            continue;
                        }
                        // The (slab, brick)'s points in this region, composited by the GP into one block.
                        std::size_t end = e;
                        int bx0 = rc, by0 = rr, bx1 = -1, by1 = -1;
                        while (end < next_point && points[rp[end]].brick == points[rp[e]].brick) {
                            const PointSquare sq = local(points[rp[end]]);
                            bx0 = std::min(bx0, std::max(sq.x0, 0));
                            by0 = std::min(by0, std::max(sq.y0, 0));
                            bx1 = std::max(bx1, std::min(sq.x1, rc - 1));
                            by1 = std::max(by1, std::min(sq.y1, rr - 1));
                            ++end;
                        }
                        block.assign(static_cast<std::size_t>(bx1 - bx0 + 1) * static_cast<std::size_t>(by1 - by0 + 1),
                                     {0, 0, 0, 0});
                        for (std::size_t m = e; m < end; ++m)
                            tally.point_pixels +=
                                composite_point_into(block, bx0, by0, bx1, by1, local(points[rp[m]]), format_);
                        draw_block_over(region, bx0, by0, bx1, by1, block, format_);
                        ++tally.blocks;
                        tally.block_pixels += block.size();
                        e = end;
                    }
                }
                Image& out = with_points ? frame.image : frame.low_resolution;
                const float scale = 1.0f / static_cast<float>(one);
                for (int y = 0; y < rr && oy + y < height; ++y)
                    for (int x = 0; x < rc && ox + x < width; ++x) {
                        const std::size_t p = region.index(x, y);
                        const float alpha = static_cast<float>(region.alpha[p]) * scale;
                        glm::vec4 v;
                        for (int ch = 0; ch < 3; ++ch)
                            v[ch] = static_cast<float>(region.color[ch][p]) * scale + (1 - alpha) * background[ch];
                        v.a = alpha;
                        out.at(ox + x, oy + y) = v;
                    }
                if (with_points) tallies[r] = tally;
            }
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

    // The machine's work: per layer, one GP task per brick with something in it.
    void record_work() {
        GpPhase& work = frame.work;
        work.groups = 1;
        work.assignment = TaskAssignment::Static;  // points live in the memory of the GP that owns their brick
        const std::size_t brick_count = static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y) *
                                        static_cast<std::size_t>(bricks_.z);
        {
            // A brick's texels and the one-texel apron its cells reach into on the high sides.
            std::vector<std::uint32_t> first_part{0};
            std::vector<BlockPart> parts;
            std::uint32_t largest = 1;
            for (std::size_t brick = 0; brick < brick_count; ++brick) {
                const glm::ivec3 bc(static_cast<int>(brick % static_cast<std::size_t>(bricks_.x)),
                                    static_cast<int>((brick / static_cast<std::size_t>(bricks_.x)) %
                                                     static_cast<std::size_t>(bricks_.y)),
                                    static_cast<int>(brick / (static_cast<std::size_t>(bricks_.x) *
                                                              static_cast<std::size_t>(bricks_.y))));
                const glm::ivec3 lo = bc * edge, hi = glm::min(lo + edge + 1, n);
                std::vector<std::uint32_t> per(static_cast<std::size_t>(machine_.renderers), 0);
                std::uint32_t total = 0;
                for (int z = lo.z; z < hi.z; ++z)
                    for (int y = lo.y; y < hi.y; ++y)
                        for (int x = lo.x; x < hi.x; ++x, ++total)
                            ++per[static_cast<std::size_t>(machine_.renderer_of_voxel({x, y, z}))];
                for (std::size_t r = 0; r < per.size(); ++r)
                    if (per[r] > 0) parts.push_back(BlockPart{static_cast<std::uint32_t>(r), per[r]});
                first_part.push_back(static_cast<std::uint32_t>(parts.size()));
                largest = std::max(largest, total);
            }
            work.blocks = std::make_shared<const BlockDirectory>(std::uint64_t{largest} * kCachedTexelBits, kUnitBits,
                                                                 std::move(first_part), std::move(parts));
        }
        const bool perspective = projection.perspective();
        const auto setup_program = static_cast<std::uint32_t>(work.region_programs.size());
        work.region_programs.push_back(programs_.setup(perspective));
        const auto quad_program = static_cast<std::uint32_t>(work.region_programs.size());
        work.region_programs.push_back(programs_.quad());
        const auto composite_program = static_cast<std::uint32_t>(work.region_programs.size());
        work.region_programs.push_back(programs_.composite());
        const auto point_program = static_cast<std::uint32_t>(work.region_programs.size());
        work.region_programs.push_back(gp_sheets ? programs_.block_over() : programs_.point());
        const auto readout_program = static_cast<std::uint32_t>(work.region_programs.size());
        work.region_programs.push_back(programs_.readout());
        work.regions.resize(static_cast<std::size_t>(machine_.renderers));
        const auto renderer_of_region = [&](std::size_t region) {
            return static_cast<std::uint32_t>(region % static_cast<std::size_t>(machine_.renderers));
        };

        struct Batch {
            std::uint64_t bits = kHeaderBits;
            std::uint32_t setups = 0;  // regions whose slice setup it carries
            std::uint32_t runs = 0;    // quads or points (or blocks) drawn from it
            std::uint64_t write_words = 0;
        };
        const auto begin_task = [&](std::uint32_t brick, bool fetch) {
            GpTask task;
            task.key = brick;
            task.first_item = static_cast<std::uint32_t>(work.items.size());
            task.item_count = 1;
            work.items.push_back(GpItem{static_cast<std::uint32_t>(work.steps.size()), 1});
            work.steps.push_back(GpStep{0, 0, fetch ? brick : kNoFetch});
            task.first_finish_op = static_cast<std::uint32_t>(work.ops.size());
            return task;
        };
        const auto end_task = [&](GpTask& task, const std::map<std::uint32_t, Batch>& batches, std::uint32_t program,
                                  std::vector<bool>* setup_sent, const std::vector<std::uint32_t>* setup_runs) {
            std::uint64_t words = 0;
            for (const auto& [renderer, batch] : batches) words += (batch.bits + 31) / 32;
            append_ops(work.ops, kWilsonPackWord, words);
            task.finish_op_count = static_cast<std::uint32_t>(work.ops.size()) - task.first_finish_op;
            task.first_batch = static_cast<std::uint32_t>(work.batches.size());
            for (const auto& [renderer, batch] : batches) {
                const auto index = static_cast<std::uint32_t>(work.batches.size());
                work.batches.push_back(PrimitiveBatch{renderer, batch.bits});
                auto& steps = work.regions[renderer].steps;
                if (setup_sent != nullptr && !(*setup_sent)[renderer]) {
                    (*setup_sent)[renderer] = true;
                    steps.push_back(RegionStep{index, setup_program, (*setup_runs)[renderer], 0});
                }
                steps.push_back(RegionStep{index, program, batch.runs, batch.write_words});
                ++counts.batches;
                counts.batch_words += (batch.bits + 31) / 32;
            }
            task.batch_count = static_cast<std::uint32_t>(batches.size());
            work.tasks.push_back(task);
            ++counts.tasks;
        };

        std::size_t next_point = 0;
        for (std::uint32_t l = 0; l < layers.size(); ++l) {
            if (layers[l].kind == LayerKind::Plane) {
                const std::size_t q0 = first_quad_of_layer[l], q1 = first_quad_of_layer[l + 1];
                if (q0 == q1) continue;
                ++counts.slices;
                // The regions this slice reaches, and per renderer how many of them it sets up.
                std::vector<char> reached(region_count, 0);
                for (std::size_t q = q0; q < q1; ++q)
                    for_each_region(quads[q].x0, quads[q].y0, quads[q].x1, quads[q].y1, rc, rr, regions_x,
                                    [&](std::size_t r) { reached[r] = 1; });
                std::vector<std::uint32_t> setup_runs(static_cast<std::size_t>(machine_.renderers), 0);
                for (std::size_t r = 0; r < region_count; ++r)
                    setup_runs[renderer_of_region(r)] += static_cast<std::uint32_t>(reached[r]);
                std::vector<bool> setup_sent(static_cast<std::size_t>(machine_.renderers), false);
                for (std::size_t first = q0; first < q1;) {
                    std::size_t end = first;
                    while (end < q1 && quads[end].brick == quads[first].brick) ++end;
                    GpTask task = begin_task(quads[first].brick, true);
                    std::map<std::uint32_t, Batch> batches;
                    std::uint64_t draws = 0, extra = 0;
                    for (std::size_t q = first; q < end; ++q) {
                        std::uint64_t here = 0;
                        for_each_region(quads[q].x0, quads[q].y0, quads[q].x1, quads[q].y1, rc, rr, regions_x,
                                        [&](std::size_t r) {
                                            Batch& batch = batches[renderer_of_region(r)];
                                            ++batch.runs;
                                            batch.bits += kQuadBits;
                                            ++here;
                                        });
                        draws += here;
                        extra += here - 1;
                    }
                    std::uint64_t setups = 0;
                    for (auto& [renderer, batch] : batches)
                        if (!setup_sent[renderer]) {
                            // This batch will carry the renderer's setup (end_task marks it sent).
                            batch.bits += kSetupBits * setup_runs[renderer];
                            setups += setup_runs[renderer];
                        }
                    // The texels the GP corrects: the brick's part of this plane with its apron.
                    glm::ivec3 brick_lo;
                    {
                        const std::uint32_t brick = quads[first].brick;
                        brick_lo =
                            glm::ivec3(static_cast<int>(brick % static_cast<std::uint32_t>(bricks_.x)),
                                       static_cast<int>((brick / static_cast<std::uint32_t>(bricks_.x)) %
                                                        static_cast<std::uint32_t>(bricks_.y)),
                                       static_cast<int>(brick / static_cast<std::uint32_t>(bricks_.x * bricks_.y))) *
                            edge;
                    }
                    const std::uint64_t plane_texels =
                        static_cast<std::uint64_t>(std::min(edge + 1, n[b] - brick_lo[b])) *
                        static_cast<std::uint64_t>(std::min(edge + 1, n[c] - brick_lo[c]));
                    append_ops(work.ops, kWilsonTexel, plane_texels);
                    append_ops(work.ops, perspective ? kWilsonQuadPerspective : kWilsonQuadParallel, end - first);
                    append_ops(work.ops, kWilsonRegionShift, extra);
                    append_ops(work.ops, kWilsonSliceSetup, setups);
                    append_ops(work.ops, kWilsonCoefficient, draws * kQuadCoefficients + setups * 9);
                    append_ops(work.ops, kWilsonBin, draws);
                    counts.quad_draws += draws;
                    end_task(task, batches, quad_program, &setup_sent, &setup_runs);
                    first = end;
                }
                for (std::size_t r = 0; r < setup_runs.size(); ++r)
                    if (setup_runs[r] > 0)
                        work.regions[r].steps.push_back(RegionStep{kNoBatch, composite_program, setup_runs[r], 0});
                continue;
            }
            // A slab: the points of each brick in it.
            while (next_point < points.size() && points[next_point].layer == l) {
                std::size_t end = next_point;
                while (end < points.size() && points[end].layer == l && points[end].brick == points[next_point].brick)
                    ++end;
                GpTask task = begin_task(points[next_point].brick, false);
                std::map<std::uint32_t, Batch> batches;
                std::uint64_t draws = 0, sheet_pixels = 0;
                std::map<std::size_t, std::array<int, 4>> blocks;  // region -> box
                for (std::size_t m = next_point; m < end; ++m) {
                    const DrawnPoint& p = points[m];
                    if (!p.drawn) continue;
                    const PointSquare& sq = p.square;
                    for_each_region(sq.x0, sq.y0, sq.x1, sq.y1, rc, rr, regions_x, [&](std::size_t r) {
                        ++draws;
                        if (!gp_sheets) {
                            Batch& batch = batches[renderer_of_region(r)];
                            ++batch.runs;
                            batch.bits += kPointBits;
                            return;
                        }
                        const int ox = static_cast<int>(r % static_cast<std::size_t>(regions_x)) * rc;
                        const int oy = static_cast<int>(r / static_cast<std::size_t>(regions_x)) * rr;
                        const int x0 = std::max(sq.x0, ox), y0 = std::max(sq.y0, oy), x1 = std::min(sq.x1, ox + rc - 1),
                                  y1 = std::min(sq.y1, oy + rr - 1);
                        sheet_pixels +=
                            static_cast<std::uint64_t>(x1 - x0 + 1) * static_cast<std::uint64_t>(y1 - y0 + 1);
                        auto [it, fresh] = blocks.try_emplace(r, std::array<int, 4>{x0, y0, x1, y1});
                        if (!fresh)
                            it->second = {std::min(it->second[0], x0), std::min(it->second[1], y0),
                                          std::max(it->second[2], x1), std::max(it->second[3], y1)};
                    });
                }
                for (const auto& [r, box] : blocks) {
                    const std::uint64_t pixels = static_cast<std::uint64_t>(box[2] - box[0] + 1) *
                                                 static_cast<std::uint64_t>(box[3] - box[1] + 1);
                    Batch& batch = batches[renderer_of_region(r)];
                    ++batch.runs;
                    batch.write_words += 2 * pixels;
                    batch.bits += 64 * pixels + 2 * 3 * kCoefficientBits;
                }
                append_ops(work.ops, kWilsonPoint, end - next_point);
                if (gp_sheets) append_ops(work.ops, kWilsonSheetPixel, sheet_pixels);
                else append_ops(work.ops, kWilsonCoefficient, draws * kPointCoefficients);
                append_ops(work.ops, kWilsonBin, draws);
                counts.point_draws += draws;
                if (batches.empty()) {
                    // Nothing to draw, but the GP shaded the points to find that out.
                    task.finish_op_count = static_cast<std::uint32_t>(work.ops.size()) - task.first_finish_op;
                    work.tasks.push_back(task);
                    ++counts.tasks;
                } else {
                    end_task(task, batches, point_program, nullptr, nullptr);
                }
                next_point = end;
            }
        }
        for (std::size_t region = 0; region < region_count; ++region) {
            const int w = std::min(rc, width - static_cast<int>(region % static_cast<std::size_t>(regions_x)) * rc);
            const int h = std::min(rr, height - static_cast<int>(region / static_cast<std::size_t>(regions_x)) * rr);
            RegionWork& rw = work.regions[renderer_of_region(region)];
            rw.steps.push_back(RegionStep{kNoBatch, readout_program, 1, 0});
            rw.readout_pixels += static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
        }
        append_ops(work.regions_on_one_processor, kWilsonQuadPixel, counts.quad_pixels);
        append_ops(work.regions_on_one_processor, kWilsonCompositePixel, counts.composited_pixels);
        append_ops(work.regions_on_one_processor, kWilsonPointPixel, counts.point_pixels);
    }

    const HybridSlicer& slicer_;
    const WilsonSettings& settings_;
    const RegionMachine& machine_;
    const HybridVolume* hybrid_;
    glm::vec3 spacing_;
    glm::ivec3 bricks_;
    const SliceFormat& format_;
    const SlicePrograms& programs_;
    const ShadedCodes& texels;
    const PointLook& look;
    const Camera& camera;
    int width, height;
    glm::vec3 background;
    ScreenProjection projection;
    const Volume& low;
    glm::ivec3 n;
    int k;
    SliceStack stack;
    int a, b, c;
    double min_spacing;
    std::int64_t one;
    int edge;
    int rc, rr, regions_x, regions_y;
    std::size_t region_count;
    bool gp_sheets;
    HybridFrame frame;
    HybridCounts& counts = frame.counts;
    std::vector<Layer> layers;
    std::vector<std::uint32_t> plane_layer, slab_layer;  // each plane's and slab's place in `layers`
    std::vector<SlicePlane> planes;
    std::vector<std::vector<Quad>> plane_quads;
    std::vector<HybridCounts> plane_counts;
    std::vector<DrawnPoint> points;
    std::vector<Quad> quads;
    std::vector<std::size_t> first_quad_of_layer;
    std::vector<std::vector<std::uint32_t>> region_quads, region_points;
};

}  // namespace

HybridSlicer::HybridSlicer(const WilsonSettings& settings, const RegionMachine& machine, const HybridVolume& hybrid,
                           glm::vec3 spacing)
    : settings_(settings),
      machine_(machine),
      hybrid_(&hybrid),
      spacing_(spacing),
      bricks_((hybrid.low_resolution().dims() + settings.brick_voxels - 1) / settings.brick_voxels),
      format_{settings.accumulator_bits},
      programs_(format_, machine.local_memory_bits) {}

std::uint32_t HybridSlicer::brick_of(const HybridPoint& point) const {
    const glm::vec3 position = hybrid_->position(point);
    const glm::ivec3 n = hybrid_->low_resolution().dims();
    const float k = static_cast<float>(hybrid_->factor());
    glm::ivec3 texel;
    for (int axis = 0; axis < 3; ++axis)
        texel[axis] = std::clamp(static_cast<int>(std::floor((position[axis] + 0.5f) / k)), 0, n[axis] - 1);
    const glm::ivec3 bc = texel / settings_.brick_voxels;
    return static_cast<std::uint32_t>(bc.x + bricks_.x * (bc.y + bricks_.y * bc.z));
}

std::vector<std::uint64_t> HybridSlicer::resident_bits_by_brick() const {
    std::vector<std::uint64_t> bits(
        static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y) * static_cast<std::size_t>(bricks_.z),
        0);
    const auto record_bits = 8 * static_cast<std::uint64_t>(hybrid_->point_format().record_bytes());
    for (const HybridPoint& p : hybrid_->points()) bits[brick_of(p)] += record_bits;
    return bits;
}

HybridFrame HybridSlicer::render(const ShadedCodes& texels, const PointLook& look, const Camera& camera, int width,
                                 int height, glm::vec3 background) const {
    return FrameBuilder(*this, settings_, machine_, *hybrid_, spacing_, bricks_, format_, programs_, texels, look,
                        camera, width, height, background)
        .build();
}

}  // namespace pp5
