#include "kernels/wilson/slice_frame_builder.h"

#include "sim/core/parallel.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pp5::slicing {

void FrameBuilder::make_layers() {
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

void FrameBuilder::make_quads() {
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
                texel[static_cast<std::size_t>(i) + static_cast<std::size_t>(n[b]) * static_cast<std::size_t>(j)] = v;
            }
        const auto at = [&](int i, int j) {
            return texel[static_cast<std::size_t>(i) + static_cast<std::size_t>(n[b]) * static_cast<std::size_t>(j)];
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

void FrameBuilder::make_points() {
    points.resize(hybrid_->points().size());
    const double grid_spacing = 1.0 / hybrid_->error_grid_factor();
    const double point_world = std::max({spacing_.x, spacing_.y, spacing_.z}) * grid_spacing;
    pp5::parallel_for(std::size_t{0}, points.size(), [&](std::size_t m) { place_point(m, grid_spacing, point_world); });
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
}

void FrameBuilder::place_point(std::size_t m, double grid_spacing, double point_world) {
    const HybridPoint& hp = hybrid_->points()[m];
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
        glm::clamp(phong_shade(look.lighting, look.colors->color(value), NormalTable::get().direction(hp.normal),
                               to_light, to_viewer, look.view.depth(world)),
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
            std::llround(alpha * static_cast<double>(color[ch]) * static_cast<double>(one)), premultiplied_alpha);
    sq.premultiplied[3] = premultiplied_alpha;
    sq.x0 = std::max(sq.x0, 0);
    sq.y0 = std::max(sq.y0, 0);
    sq.x1 = std::min(sq.x1, width - 1);
    sq.y1 = std::min(sq.y1, height - 1);
    if (sq.x1 < sq.x0 || sq.y1 < sq.y0) p.offscreen = true;
    else p.drawn = true;
}

void FrameBuilder::order_quads() {
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

void FrameBuilder::bin_by_region() {
    region_quads.resize(region_count);
    region_points.resize(region_count);
    for (std::size_t q = 0; q < quads.size(); ++q)
        for_each_region(quads[q].x0, quads[q].y0, quads[q].x1, quads[q].y1, rc, rr, regions_x,
                        [&](std::size_t r) { region_quads[r].push_back(static_cast<std::uint32_t>(q)); });
    for (std::size_t m = 0; m < points.size(); ++m)
        if (points[m].drawn)
            for_each_region(points[m].square.x0, points[m].square.y0, points[m].square.x1, points[m].square.y1, rc, rr,
                            regions_x,
                            [&](std::size_t r) { region_points[r].push_back(static_cast<std::uint32_t>(m)); });
}

}  // namespace pp5::slicing
