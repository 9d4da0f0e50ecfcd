#include "kernels/yuan/hybrid_splatter.h"

#include "kernels/yuan/screen_primitives.h"
#include "kernels/yuan/splat_geometry.h"
#include "kernels/yuan/yuan_costs.h"
#include "sim/core/parallel.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace pp5 {

namespace {

constexpr std::uint32_t kUnitBits = 48;         // a voxel as the renderers stream it: RGBA and its place in the brick
constexpr std::uint32_t kCachedVoxelBits = 64;  // and as a GP keeps it
constexpr std::uint64_t kHeaderBits = 64;       // a batch's header: kind, band, brick, count
constexpr std::uint64_t kCoefficientBits = 32;
constexpr std::uint64_t kConstantBits = 16;

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

bool key_less(const Item& a, const Item& b) {
    if (a.band != b.band) return a.band < b.band;
    if (a.brick != b.brick) return a.brick < b.brick;
    if (a.depth != b.depth) return a.depth < b.depth;
    return a.voxel < b.voxel;
}

// A primitive's place in one region's list, and the pixels it changed there.
struct RegionEntry {
    std::uint32_t item = 0;
    std::uint32_t pixels = 0;
};

}  // namespace

HybridSplatter::HybridSplatter(const YuanSettings& settings, const RegionMachine& machine, glm::ivec3 dims,
                               glm::vec3 spacing)
    : settings_(settings),
      machine_(machine),
      dims_(dims),
      spacing_(spacing),
      bricks_((dims + settings.brick_voxels - 1) / settings.brick_voxels),
      format_{settings.accumulator_bits, settings.footprint_table_bits},
      programs_(format_,
                settings.footprint_index == FootprintIndex::Exact ? SplatIndexMode::Exact : SplatIndexMode::Affine,
                settings.splat_compositing == SplatCompositing::Over ? SplatBlend::Over : SplatBlend::Sheet,
                machine.local_memory_bits),
      kernel_(settings.kernel_sigma, settings.kernel_radius),
      corrected_(kernel_, settings.footprint_table_bits, settings.accumulator_bits,
                 glm::radians(settings.footprint_alpha_step_degrees), true),
      plain_(kernel_, settings.footprint_table_bits, settings.accumulator_bits, 1.0, false) {}

SplatFrame HybridSplatter::render(const ShadedCodes& voxels, const Camera& camera, int width, int height,
                                  glm::vec3 background) const {
    const ScreenProjection projection(camera, width, height);
    const double h = std::min({spacing_.x, spacing_.y, spacing_.z});
    const double kernel_world = settings_.kernel_radius * h;
    const bool exact = settings_.footprint_index == FootprintIndex::Exact && projection.perspective();
    const bool corrected = !exact && projection.perspective();
    const FootprintTables& tables = this->tables(corrected);
    const std::int64_t one = format_.one();
    SplatFrame frame;
    SplatCounts& counts = frame.counts;

    // 1. The non-transparent voxels of each brick, transformed and split (bricks in parallel, then in order).
    const int edge = settings_.brick_voxels;
    const auto brick_count =
        static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y) * static_cast<std::size_t>(bricks_.z);
    std::vector<std::vector<Item>> per_brick(brick_count);
    std::vector<std::vector<std::uint32_t>> brick_parts(brick_count);  // per renderer: voxels streamed
    pp5::parallel_for(std::size_t{0}, brick_count, [&](std::size_t b) {
        const glm::ivec3 bc(
            static_cast<int>(b % static_cast<std::size_t>(bricks_.x)),
            static_cast<int>((b / static_cast<std::size_t>(bricks_.x)) % static_cast<std::size_t>(bricks_.y)),
            static_cast<int>(b / (static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y))));
        const glm::ivec3 lo = bc * edge;
        const glm::ivec3 hi = glm::min(lo + edge, dims_);
        std::vector<std::uint32_t>& parts = brick_parts[b];
        parts.assign(static_cast<std::size_t>(machine_.renderers), 0);
        for (int z = lo.z; z < hi.z; ++z)
            for (int y = lo.y; y < hi.y; ++y)
                for (int x = lo.x; x < hi.x; ++x) {
                    const std::size_t v = static_cast<std::size_t>(x) +
                                          static_cast<std::size_t>(dims_.x) *
                                              (static_cast<std::size_t>(y) +
                                               static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(z));
                    if (voxels.transparent(v)) continue;
                    Item item;
                    item.brick = static_cast<std::uint32_t>(b);
                    item.voxel = static_cast<std::uint32_t>(v);
                    item.eye = projection.to_eye(glm::vec3(x, y, z) * spacing_);
                    item.depth = static_cast<float>(item.eye.z);
                    const double spacing_pixels = h * projection.pixels_per_unit(item.eye.z);
                    if (projection.perspective() && item.eye.z <= kernel_world) item.kind = Kind::Culled;
                    else if (settings_.primitives == PrimitiveMode::AllSplats) item.kind = Kind::Splat;
                    else if (settings_.primitives == PrimitiveMode::AllPoints) item.kind = Kind::Point;
                    else item.kind = spacing_pixels > settings_.switch_pixels ? Kind::Splat : Kind::Point;
                    per_brick[b].push_back(item);
                    ++parts[static_cast<std::size_t>(machine_.renderer_of_voxel({x, y, z}))];
                }
    });
    std::vector<Item> items;
    for (auto& v : per_brick) items.insert(items.end(), v.begin(), v.end());
    per_brick.clear();
    counts.voxels = items.size();

    // 2. Bands by depth, then the order every renderer takes: (band, brick, depth).
    float nearest = std::numeric_limits<float>::max();
    for (const Item& item : items) nearest = std::min(nearest, item.depth);
    const double band_depth = settings_.band_voxels * h;
    // Bands are centred on the nearest voxel's depth, so that a layer of voxels at one depth (a slab face
    // on) falls in the middle of a band, not on the rounding edge between two.
    for (Item& item : items)
        item.band = static_cast<std::uint32_t>(std::floor((item.depth - nearest) / band_depth + 0.5));
    pp5::parallel_sort(items.begin(), items.end(), key_less);

    // 3. Each voxel's primitive (in parallel; each from its own voxel only).
    const double point_radius = settings_.point_radius_pixels();
    std::vector<ScreenPrimitive> primitives(items.size());
    pp5::parallel_for(std::size_t{0}, items.size(), [&](std::size_t k) {
        Item& item = items[k];
        ScreenPrimitive& p = primitives[k];
        const glm::vec4 rgba = voxels.value(item.voxel);
        if (item.kind == Kind::Splat) {
            std::optional<ScreenPrimitive> splat =
                splat_primitive(projection, item.eye, kernel_world, rgba, tables, exact, format_, width, height);
            if (splat) p = *splat;
            else item.kind = Kind::Culled;
        } else if (item.kind == Kind::Point) {
            p = point_primitive(projection, item.eye, h * projection.pixels_per_unit(item.eye.z), rgba, point_radius,
                                format_, width, height);
        }
    });

    // 4. Screen regions, and each region's primitives in the renderers' order.
    const int rc = machine_.region_columns, rr = machine_.region_rows;
    const int regions_x = (width + rc - 1) / rc, regions_y = (height + rr - 1) / rr;
    const std::size_t region_count = static_cast<std::size_t>(regions_x) * static_cast<std::size_t>(regions_y);
    std::vector<std::vector<RegionEntry>> lists(region_count);
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
        for (int ry = p.y0 / rr; ry <= p.y1 / rr; ++ry)
            for (int rx = p.x0 / rc; rx <= p.x1 / rc; ++rx)
                lists[static_cast<std::size_t>(ry) * static_cast<std::size_t>(regions_x) + static_cast<std::size_t>(rx)]
                    .push_back(RegionEntry{static_cast<std::uint32_t>(k), 0});
    }

    // The footprint rows the splats use, made here once rather than looked up under a lock per draw.
    std::map<int, const PpTable*> row_tables;
    for (std::size_t k = 0; k < items.size(); ++k)
        if (items[k].kind == Kind::Splat && primitives[k].visible()) row_tables.emplace(primitives[k].row, nullptr);
    for (auto& [row, table] : row_tables) table = &tables.table(row);

    // 5. Every region drawn as its renderer draws it (regions in parallel: each depends on its own list).
    frame.image = Image(width, height);
    frame.primitive_map = Image(width, height);
    std::vector<std::vector<std::uint32_t>> composited(region_count);  // per region: the bands it composited
    std::vector<std::uint64_t> composited_pixels(region_count, 0);
    const SplatIndexMode mode = exact ? SplatIndexMode::Exact : SplatIndexMode::Affine;
    const SplatBlend blend = programs_.blend();
    const bool gp_sheets = settings_.point_path == PointPath::GpSheets;
    pp5::parallel_for(std::size_t{0}, region_count, [&](std::size_t r) {
        const int ox = static_cast<int>(r % static_cast<std::size_t>(regions_x)) * rc;
        const int oy = static_cast<int>(r / static_cast<std::size_t>(regions_x)) * rr;
        RegionPixels region(rc, rr);
        std::vector<std::uint8_t> kinds_drawn(static_cast<std::size_t>(rc) * static_cast<std::size_t>(rr),
                                              0);  // bit 0 splat, 1 point
        std::vector<RegionEntry>& list = lists[r];
        bool sheet_holds = false;
        std::uint32_t band = 0;
        const auto close_band = [&] {
            if (!sheet_holds) return;
            composited_pixels[r] += composite_band(region, format_);
            composited[r].push_back(band);
            sheet_holds = false;
        };
        std::vector<std::array<std::int32_t, 4>> block;
        for (std::size_t e = 0; e < list.size();) {
            const Item& item = items[list[e].item];
            if (item.band != band) {
                close_band();
                band = item.band;
            }
            const ScreenPrimitive& p = primitives[list[e].item];
            const int lx0 = p.x0 - ox, ly0 = p.y0 - oy, lx1 = p.x1 - ox, ly1 = p.y1 - oy;
            const auto mark = [&](int x0, int y0, int x1, int y1, std::uint8_t bit) {
                for (int y = std::max(y0, 0); y <= std::min(y1, rr - 1); ++y)
                    for (int x = std::max(x0, 0); x <= std::min(x1, rc - 1); ++x)
                        kinds_drawn[region.index(x, y)] |= bit;
            };
            if (item.kind == Kind::Splat) {
                const SplatDraw draw = splat_draw(p, ox, oy, mode == SplatIndexMode::Exact);
                list[e].pixels = draw_splat(region, draw, *row_tables.at(p.row), format_, mode, blend);
                if (blend == SplatBlend::Sheet) sheet_holds = true;
                mark(lx0, ly0, lx1, ly1, 1);
                ++e;
                continue;
            }
            // Points: on the renderer path each is drawn; on the GPs' path the chunk's points in this region
            // are filtered into one block, which the renderer adds to its sheet.
            sheet_holds = true;
            if (!gp_sheets) {
                list[e].pixels = draw_point(region, point_draw(p, ox, oy), format_);
                mark(lx0, ly0, lx1, ly1, 2);
                ++e;
                continue;
            }
            std::size_t end = e;
            int bx0 = rc, by0 = rr, bx1 = -1, by1 = -1;
            while (end < list.size() && items[list[end].item].band == item.band &&
                   items[list[end].item].brick == item.brick && items[list[end].item].kind == Kind::Point) {
                const ScreenPrimitive& q = primitives[list[end].item];
                bx0 = std::min(bx0, std::max(q.x0 - ox, 0));
                by0 = std::min(by0, std::max(q.y0 - oy, 0));
                bx1 = std::max(bx1, std::min(q.x1 - ox, rc - 1));
                by1 = std::max(by1, std::min(q.y1 - oy, rr - 1));
                ++end;
            }
            const int bw = bx1 - bx0 + 1;
            block.assign(static_cast<std::size_t>(bw) * static_cast<std::size_t>(by1 - by0 + 1), {0, 0, 0, 0});
            for (std::size_t k = e; k < end; ++k)
                list[k].pixels =
                    filter_point(point_draw(primitives[list[k].item], ox, oy), format_, bx0, by0, bx1, by1, block);
            add_sheet_block(region, bx0, by0, bx1, by1, block, format_);
            mark(bx0, by0, bx1, by1, 2);
            e = end;
        }
        close_band();
        // The region's pixels: the volume over the background.
        const float scale = 1.0f / static_cast<float>(one);
        for (int y = 0; y < rr && oy + y < height; ++y)
            for (int x = 0; x < rc && ox + x < width; ++x) {
                const std::size_t p = region.index(x, y);
                const float a = static_cast<float>(region.alpha[p]) * scale;
                glm::vec4 out;
                for (int c = 0; c < 3; ++c)
                    out[c] = static_cast<float>(region.color[c][p]) * scale + (1 - a) * background[c];
                out.a = a;
                frame.image.at(ox + x, oy + y) = out;
                const std::uint8_t k = kinds_drawn[p];
                frame.primitive_map.at(ox + x, oy + y) = (k & 1)   ? glm::vec4(a, 0, 0, 1)
                                                         : (k & 2) ? glm::vec4(a, a, a, 1)
                                                                   : glm::vec4(0, 0, 0, 1);
            }
    });
    for (std::size_t r = 0; r < region_count; ++r) {
        counts.primitives_per_region.push_back(lists[r].size());
        counts.band_composites += composited[r].size();
        counts.composited_pixels += composited_pixels[r];
    }

    // 6. The machine's work: one GP task per (band, brick) chunk, batches to the renderers, their steps.
    GpPhase& work = frame.work;
    work.groups = 1;
    work.assignment = settings_.brick_assignment;
    {
        std::vector<std::uint32_t> first_part{0};
        std::vector<BlockPart> parts;
        std::uint32_t largest = 1;
        for (const auto& brick : brick_parts) {
            std::uint32_t total = 0;
            for (std::size_t r = 0; r < brick.size(); ++r) {
                if (brick[r] > 0) parts.push_back(BlockPart{static_cast<std::uint32_t>(r), brick[r]});
                total += brick[r];
            }
            largest = std::max(largest, total);
            first_part.push_back(static_cast<std::uint32_t>(parts.size()));
        }
        work.blocks = std::make_shared<const BlockDirectory>(std::uint64_t{largest} * kCachedVoxelBits, kUnitBits,
                                                             std::move(first_part), std::move(parts));
    }
    // Region programs: the splat program of each footprint row used, then the others.
    std::map<int, std::uint32_t> splat_program;
    for (const auto& [row, table] : row_tables) {
        splat_program.emplace(row, static_cast<std::uint32_t>(work.region_programs.size()));
        work.region_programs.push_back(programs_.splat(*table));
    }
    counts.footprint_rows = splat_program.size();
    const auto point_program = static_cast<std::uint32_t>(work.region_programs.size());
    work.region_programs.push_back(gp_sheets ? programs_.sheet_add() : programs_.point());
    const auto composite_program = static_cast<std::uint32_t>(work.region_programs.size());
    work.region_programs.push_back(programs_.band_composite());
    const auto readout_program = static_cast<std::uint32_t>(work.region_programs.size());
    work.region_programs.push_back(programs_.readout());
    work.regions.resize(static_cast<std::size_t>(machine_.renderers));
    const auto renderer_of_region = [&](std::size_t region) {
        return region % static_cast<std::size_t>(machine_.renderers);
    };

    // Where each item stands in each region's list (for its pixel counts), walked in item order.
    std::vector<std::size_t> cursor(region_count, 0);
    std::vector<std::size_t> next_composite(region_count, 0);
    const std::uint64_t splat_bits =
        (exact ? 2 : 1) * 6 * kCoefficientBits + 4 * kConstantBits + kConstantBits;  // quadratics, constants, table row
    const std::uint64_t point_bits = 4 * 4 * kCoefficientBits;  // four paraboloids of four coefficients
    std::uint64_t splat_pixels = 0, point_pixels = 0;
    for (std::size_t first = 0; first < items.size();) {
        std::size_t end = first;
        while (end < items.size() && items[end].band == items[first].band && items[end].brick == items[first].brick)
            ++end;
        ++counts.chunks;
        // Per renderer touched: its batch's bits and its steps.
        struct Batch {
            std::uint64_t bits = kHeaderBits;
            std::map<std::uint32_t, std::uint32_t> runs;  // program -> runs
            std::uint64_t write_words = 0;
        };
        std::map<std::uint32_t, Batch> batches;
        std::uint64_t splats = 0, points = 0, extra_regions = 0, coefficients = 0, bins = 0, sheet_pixels = 0;
        std::map<std::size_t, std::pair<glm::ivec2, glm::ivec2>> point_blocks;  // region -> box, for the GPs' sheets
        for (std::size_t k = first; k < end; ++k) {
            if (items[k].kind == Kind::Culled || !primitives[k].visible()) continue;
            const ScreenPrimitive& p = primitives[k];
            const bool splat = items[k].kind == Kind::Splat;
            (splat ? splats : points) += 1;
            std::uint64_t regions_here = 0;
            for (int ry = p.y0 / rr; ry <= p.y1 / rr; ++ry)
                for (int rx = p.x0 / rc; rx <= p.x1 / rc; ++rx) {
                    const std::size_t region = static_cast<std::size_t>(ry) * static_cast<std::size_t>(regions_x) +
                                               static_cast<std::size_t>(rx);
                    RegionEntry& entry = lists[region][cursor[region]++];
                    ++regions_here;
                    ++bins;
                    Batch& batch = batches[static_cast<std::uint32_t>(renderer_of_region(region))];
                    if (splat) {
                        splat_pixels += entry.pixels;
                        ++batch.runs[splat_program.at(p.row)];
                        batch.bits += splat_bits;
                        coefficients += (exact ? 12 : 6) + 4;
                        ++counts.splat_regions;
                    } else {
                        ++counts.point_regions;
                        if (gp_sheets) {
                            sheet_pixels += entry.pixels;
                            auto [it, fresh] =
                                point_blocks.try_emplace(region, glm::ivec2(p.x0, p.y0), glm::ivec2(p.x1, p.y1));
                            if (!fresh) {
                                it->second.first = glm::min(it->second.first, glm::ivec2(p.x0, p.y0));
                                it->second.second = glm::max(it->second.second, glm::ivec2(p.x1, p.y1));
                            }
                        } else {
                            point_pixels += entry.pixels;
                            ++batch.runs[point_program];
                            batch.bits += point_bits;
                            coefficients += 16;
                        }
                    }
                }
            extra_regions += regions_here - 1;
        }
        for (const auto& [region, box] : point_blocks) {
            // The block covers the chunk's points' box within the region: two words (four 16-bit values) a pixel.
            const int ox = static_cast<int>(region % static_cast<std::size_t>(regions_x)) * rc;
            const int oy = static_cast<int>(region / static_cast<std::size_t>(regions_x)) * rr;
            const glm::ivec2 lo = glm::max(box.first, glm::ivec2(ox, oy));
            const glm::ivec2 hi = glm::min(box.second, glm::ivec2(ox + rc - 1, oy + rr - 1));
            const std::uint64_t pixels =
                static_cast<std::uint64_t>(hi.x - lo.x + 1) * static_cast<std::uint64_t>(hi.y - lo.y + 1);
            Batch& batch = batches[static_cast<std::uint32_t>(renderer_of_region(region))];
            ++batch.runs[point_program];
            batch.write_words += 2 * pixels;
            batch.bits += 64 * pixels + 64;
        }
        // The task: fetch the brick (a cache hit after its first chunk on this GP), then the chunk's work.
        GpTask task;
        task.key = items[first].brick;
        task.first_item = static_cast<std::uint32_t>(work.items.size());
        task.item_count = 1;
        work.items.push_back(GpItem{static_cast<std::uint32_t>(work.steps.size()), 1});
        work.steps.push_back(GpStep{0, 0, items[first].brick});
        task.first_finish_op = static_cast<std::uint32_t>(work.ops.size());
        std::uint64_t words = 0;
        for (const auto& [renderer, batch] : batches) words += (batch.bits + 31) / 32;
        append_ops(work.ops, kYuanVoxel, end - first);
        append_ops(work.ops, kYuanSplatSetup, splats);
        append_ops(work.ops, kYuanRegionShift, extra_regions);
        append_ops(work.ops, kYuanCoefficient, coefficients);
        if (gp_sheets) append_ops(work.ops, kYuanSheetPixel, sheet_pixels);
        else append_ops(work.ops, kYuanPointSetup, points);
        append_ops(work.ops, kYuanBin, bins);
        append_ops(work.ops, kYuanPackWord, words);
        task.finish_op_count = static_cast<std::uint32_t>(work.ops.size()) - task.first_finish_op;
        task.first_batch = static_cast<std::uint32_t>(work.batches.size());
        for (const auto& [renderer, batch] : batches) {
            const auto index = static_cast<std::uint32_t>(work.batches.size());
            work.batches.push_back(PrimitiveBatch{renderer, batch.bits});
            // A batch exists only for a renderer something was binned to, so it always has a step.
            for (const auto& [program, runs] : batch.runs)
                work.regions[renderer].steps.push_back(
                    RegionStep{index, program, runs, program == point_program && gp_sheets ? batch.write_words : 0});
            ++counts.batches;
            counts.batch_words += (batch.bits + 31) / 32;
        }
        task.batch_count = static_cast<std::uint32_t>(batches.size());
        work.tasks.push_back(task);
        // At a band's end each renderer composites the sheets of its regions that hold something.
        if (end == items.size() || items[end].band != items[first].band) {
            const std::uint32_t band = items[first].band;
            std::vector<std::uint32_t> composites(static_cast<std::size_t>(machine_.renderers), 0);
            for (std::size_t region = 0; region < region_count; ++region) {
                std::size_t& next = next_composite[region];
                if (next < composited[region].size() && composited[region][next] == band) {
                    ++next;
                    ++composites[renderer_of_region(region)];
                }
            }
            for (std::size_t renderer = 0; renderer < composites.size(); ++renderer)
                if (composites[renderer] > 0)
                    work.regions[renderer].steps.push_back(
                        RegionStep{kNoBatch, composite_program, composites[renderer], 0});
            ++counts.bands;
        }
        first = end;
    }
    counts.splat_pixels = splat_pixels;
    counts.point_pixels = point_pixels;
    for (std::size_t region = 0; region < region_count; ++region) {
        const int w = std::min(rc, width - static_cast<int>(region % static_cast<std::size_t>(regions_x)) * rc);
        const int hgt = std::min(rr, height - static_cast<int>(region / static_cast<std::size_t>(regions_x)) * rr);
        RegionWork& rw = work.regions[renderer_of_region(region)];
        rw.steps.push_back(RegionStep{kNoBatch, readout_program, 1, 0});
        rw.readout_pixels += static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(hgt);
    }
    // What a lone processor does instead of the renderers: every pixel each primitive changed.
    append_ops(work.regions_on_one_processor, kYuanSplatPixel, counts.splat_pixels);
    if (!gp_sheets) append_ops(work.regions_on_one_processor, kYuanPointPixel, counts.point_pixels);
    append_ops(work.regions_on_one_processor, kYuanCompositePixel, counts.composited_pixels);
    return frame;
}

}  // namespace pp5
