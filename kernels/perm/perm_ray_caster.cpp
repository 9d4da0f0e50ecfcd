#include "kernels/perm/perm_ray_caster.h"

#include "kernels/perm/perm_costs.h"
#include "scene/reference/ray_march.h"
#include "scene/reference/sample_shader.h"
#include "scene/reference/shading_view.h"
#include "scene/render/front_to_back.h"
#include "sim/core/parallel.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

namespace {

// One ray's recorded work: a fetch of each cell it entered, with the samples before it, then the rest.
struct RayRecord {
    struct Touch {
        std::uint32_t block;
        std::uint32_t samples, empty, leaped, cued;
    };
    std::vector<Touch> touches;
    std::uint32_t tail_samples = 0, tail_empty = 0, tail_leaped = 0, tail_cued = 0;
};

struct TileResult {
    std::vector<RayRecord> rays;
    PermCastCounts counts;
};

// The picture's square tiles, row-major: a GP task casts one tile's rays.
struct TileGrid {
    int edge, across, width, height;

    ScreenRect rect(int t) const {
        const int x0 = (t % across) * edge, y0 = (t / across) * edge;
        return {static_cast<std::uint16_t>(x0), static_cast<std::uint16_t>(y0),
                static_cast<std::uint16_t>(std::min(width, x0 + edge) - x0),
                static_cast<std::uint16_t>(std::min(height, y0 + edge) - y0)};
    }
};

// The GPs' work: a task per tile, an item per ray, a step per cell's record fetched through `blocks`
// (none: the records are the GP's own and no step fetches), the pixels last.
GpPhase record_tiles(const std::vector<TileResult>& results, const TileGrid& grid,
                     std::shared_ptr<const BlockDirectory> blocks, bool pp_shaded) {
    GpPhase work;
    work.groups = 1;
    work.assignment = TaskAssignment::Static;
    const bool fetches = blocks != nullptr;
    work.blocks = std::move(blocks);
    constexpr int kRowSkew = 7;  // as Levoy's kernel: each row of tile keys skewed, so a GP's tiles spread out
    const auto step = [&](std::uint32_t samples, std::uint32_t empty, std::uint32_t leaped, std::uint32_t cued,
                          std::uint32_t block, bool setup) {
        GpStep s{static_cast<std::uint32_t>(work.ops.size()), 0, fetches ? block : kNoFetch};
        if (setup) append_ops(work.ops, kPermRaySetup, 1);
        append_ops(work.ops, pp_shaded ? kPermShadedSample : kPermSample, samples);
        append_ops(work.ops, kPermDepthCue, cued);
        append_ops(work.ops, kPermEmptySample, empty);
        append_ops(work.ops, kPermLeapedSample, leaped);
        s.op_count = static_cast<std::uint32_t>(work.ops.size()) - s.first_op;
        work.steps.push_back(s);
    };
    for (std::size_t t = 0; t < results.size(); ++t) {
        const TileResult& result = results[t];
        const int tile = static_cast<int>(t);
        GpTask task;
        task.key = static_cast<std::uint32_t>(tile + kRowSkew * (tile / grid.across));
        task.screen = grid.rect(tile);
        task.first_item = static_cast<std::uint32_t>(work.items.size());
        for (const RayRecord& r : result.rays) {
            GpItem item{static_cast<std::uint32_t>(work.steps.size()), 0};
            bool setup = true;
            for (const RayRecord::Touch& touch : r.touches) {
                step(touch.samples, touch.empty, touch.leaped, touch.cued, touch.block, setup);
                setup = false;
                ++item.step_count;
            }
            step(r.tail_samples, r.tail_empty, r.tail_leaped, r.tail_cued, kNoFetch, setup);
            ++item.step_count;
            work.items.push_back(item);
        }
        task.item_count = static_cast<std::uint32_t>(result.rays.size());
        task.first_finish_op = static_cast<std::uint32_t>(work.ops.size());
        append_ops(work.ops, kPermPixel, result.rays.size());
        task.finish_op_count = static_cast<std::uint32_t>(work.ops.size()) - task.first_finish_op;
        task.pixels = static_cast<std::uint32_t>(result.rays.size());
        work.tasks.push_back(task);
    }
    return work;
}

}  // namespace

PermCastCounts& PermCastCounts::operator+=(const PermCastCounts& c) {
    rays += c.rays;
    rays_terminated += c.rays_terminated;
    samples += c.samples;
    empty_samples += c.empty_samples;
    leaped_samples += c.leaped_samples;
    cell_fetches += c.cell_fetches;
    carried_lookups += c.carried_lookups;
    return *this;
}

PermRayCaster::PermRayCaster(const PermStructure& structure, glm::vec3 spacing, const PermSettings& settings,
                             std::function<std::uint32_t(glm::ivec3)> renderer_of_cell, const PermRecordShading* shaded)
    : structure_(&structure), spacing_(spacing), settings_(settings), shaded_(shaded) {
    // A block may be leapt over when none of its cells is a candidate: mark every candidate's corners.
    const glm::ivec3 d = structure.dims();
    std::vector<float> marks(
        static_cast<std::size_t>(d.x) * static_cast<std::size_t>(d.y) * static_cast<std::size_t>(d.z), 0.0f);
    for (std::uint32_t c = 0; c < structure.candidates(); ++c) {
        const glm::ivec3 o = structure.cell_origin(c);
        for (int k = 0; k < 8; ++k) {
            const glm::ivec3 v = o + glm::ivec3(k & 1, (k >> 1) & 1, k >> 2);
            marks[static_cast<std::size_t>(v.x) +
                  static_cast<std::size_t>(d.x) *
                      (static_cast<std::size_t>(v.y) + static_cast<std::size_t>(d.y) * static_cast<std::size_t>(v.z))] =
                1.0f;
        }
    }
    occupancy_ = occupancy_from_opacity(d, marks);
    if (renderer_of_cell) {
        const auto directory = [&](std::uint32_t words) {
            std::vector<std::uint32_t> first_part;
            std::vector<BlockPart> parts;
            for (std::uint32_t c = 0; c < structure.candidates(); ++c) {
                first_part.push_back(static_cast<std::uint32_t>(parts.size()));
                parts.push_back(BlockPart{renderer_of_cell(structure.cell_origin(c)), words});
            }
            first_part.push_back(static_cast<std::uint32_t>(parts.size()));
            return std::make_shared<const BlockDirectory>(std::uint64_t{words} * 32, 32, std::move(first_part),
                                                          std::move(parts));
        };
        if (shaded_ != nullptr) {
            records_ = directory(shaded_->fetched_words(false));
            cued_records_ = directory(shaded_->fetched_words(true));
        } else {
            records_ = directory(static_cast<std::uint32_t>((structure.memory().record_bytes() + 3) / 4));
        }
    }
}

PermFrame PermRayCaster::cast(const Classification& classification, const ColorMap& colors,
                              const PhongLighting& lighting, const Camera& camera, const PermCastSettings& cs) const {
    const PermStructure& perm = *structure_;
    const glm::ivec3 dims = perm.dims();
    const detail::MarchFrame frame(dims, spacing_, cs.sample_step);
    const PixelRays rays(camera, cs.width, cs.height);
    const ShadingView view = make_shading_view(camera, dims, spacing_);
    const SampleShader shader(colors, lighting, view, spacing_);
    // PP-shaded records are shaded without the depth cue, which dims only the directly lit part:
    // the GP takes the ambient part from the density's base colour and divides the rest.
    const bool cue = shaded_ != nullptr && lighting.depth_cue_k2 != 0.0f;
    const int tile = settings_.tile_pixels;
    const int tiles_x = (cs.width + tile - 1) / tile, tiles_y = (cs.height + tile - 1) / tile;
    const int tiles = tiles_x * tiles_y;
    PermFrame out;
    out.image = Image(cs.width, cs.height);
    std::vector<TileResult> results(static_cast<std::size_t>(tiles));
    pp5::parallel_for(0, tiles, [&](int t) {
        TileResult& result = results[static_cast<std::size_t>(t)];
        const int x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
        for (int py = y0; py < std::min(y0 + tile, cs.height); ++py)
            for (int px = x0; px < std::min(x0 + tile, cs.width); ++px) {
                RayRecord record;
                FrontToBack color(cs.sample_step, cs.termination_opacity);
                ++result.counts.rays;
                std::int64_t current = -1;                       // the cell whose record the ray holds
                std::uint32_t samples = 0, empty = 0, cued = 0;  // since the last fetch
                std::uint64_t ray_samples = 0, ray_empty = 0;
                if (const auto ray = detail::clip_to_volume(rays.ray(px, py), frame)) {
                    const detail::MarchCounts marched = detail::march(*ray, &occupancy_, [&](int, glm::vec3 position) {
                        const glm::vec3 p = glm::clamp(position, glm::vec3(0.0f), glm::vec3(dims - 1));
                        const glm::ivec3 cell = glm::min(glm::ivec3(p), dims - 2);
                        const std::int32_t candidate = perm.index(cell.x, cell.y, cell.z);
                        if (candidate == PermStructure::kNull) {
                            ++empty;
                            ++ray_empty;
                            return false;
                        }
                        if (candidate != current) {
                            record.touches.push_back({static_cast<std::uint32_t>(candidate), samples, empty, 0, cued});
                            samples = empty = cued = 0;
                            current = candidate;
                            ++result.counts.cell_fetches;
                        }
                        ++samples;
                        ++ray_samples;
                        const glm::vec3 fraction = p - glm::vec3(cell);
                        if (shaded_ != nullptr) {
                            const int at = perm.density_position(fraction, &result.counts.carried_lookups);
                            const glm::vec4 rgba = shaded_->at(static_cast<std::uint32_t>(candidate), at);
                            if (!(rgba.a > 0.0f)) return false;
                            glm::vec3 rgb(rgba);
                            if (cue) {
                                const glm::vec3 ambient =
                                    colors.color(perm.density_at(static_cast<std::uint32_t>(candidate), at)) *
                                    lighting.ambient;
                                const float divisor =
                                    lighting.depth_cue_k1 + lighting.depth_cue_k2 * view.depth(p * spacing_);
                                rgb = ambient + glm::max(rgb - ambient, glm::vec3(0.0f)) / divisor;
                                ++cued;
                            }
                            return color.add(glm::clamp(rgb, 0.0f, 1.0f), rgba.a);
                        }
                        const PermStructure::Sample s = perm.lookup(static_cast<std::uint32_t>(candidate), fraction,
                                                                    &result.counts.carried_lookups);
                        const float alpha = classification.opacity(s.value, glm::length(s.gradient));
                        if (!(alpha > 0.0f)) return false;
                        return color.add(shader.shade(s.value, s.gradient, p * spacing_), alpha);
                    });
                    record.tail_leaped = static_cast<std::uint32_t>(marched.skipped);
                    result.counts.leaped_samples += marched.skipped;
                    if (marched.terminated) ++result.counts.rays_terminated;
                }
                record.tail_samples = samples;
                record.tail_empty = empty;
                record.tail_cued = cued;
                result.counts.samples += ray_samples;
                result.counts.empty_samples += ray_empty;
                out.image.at(px, py) = color.over(cs.background);
                result.rays.push_back(std::move(record));
            }
    });

    // The recorded work, tile by tile.
    const TileGrid grid{tile, tiles_x, cs.width, cs.height};
    out.work = record_tiles(results, grid, records_ ? (cue ? cued_records_ : records_) : nullptr, shaded_ != nullptr);
    for (const TileResult& result : results) out.counts += result.counts;
    return out;
}

}  // namespace pp5
