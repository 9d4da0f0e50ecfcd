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
#include <optional>

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

// What every ray of a frame reads: the structure, the view and how a sample is shaded.
struct FrameLook {
    const PermStructure& perm;
    const OccupancyGrid& occupancy;
    const PermRecordShading* shaded;  // null: the GP classifies and shades each sample itself
    const Classification& classification;
    const ColorMap& colors;
    const PhongLighting& lighting;
    const ShadingView& view;
    const SampleShader& shader;
    glm::vec3 spacing;
    bool cue;  // the GP depth-cues PP-shaded samples
};

// One ray through the PERM: its colour, and the cells whose records it fetched, in order, with the
// samples taken between fetches.
class PermRay {
public:
    PermRay(const FrameLook& look, const PermCastSettings& cs, PermCastCounts& counts)
        : look_(look), dims_(look.perm.dims()), color_(cs.sample_step, cs.termination_opacity), counts_(counts) {}

    // Marches the clipped ray (none: it misses the volume) and returns its record.
    RayRecord cast(const std::optional<detail::ClippedRay>& ray) {
        ++counts_.rays;
        if (ray) {
            const detail::MarchCounts marched =
                detail::march(*ray, &look_.occupancy, [&](int, glm::vec3 position) { return sample(position); });
            record_.tail_leaped = static_cast<std::uint32_t>(marched.skipped);
            counts_.leaped_samples += marched.skipped;
            if (marched.terminated) ++counts_.rays_terminated;
        }
        record_.tail_samples = samples_;
        record_.tail_empty = empty_;
        record_.tail_cued = cued_;
        counts_.samples += ray_samples_;
        counts_.empty_samples += ray_empty_;
        return std::move(record_);
    }

    glm::vec4 color(glm::vec3 background) const { return color_.over(background); }

private:
    // One sample: true when the ray is now opaque.
    bool sample(glm::vec3 position) {
        const glm::vec3 p = glm::clamp(position, glm::vec3(0.0f), glm::vec3(dims_ - 1));
        const glm::ivec3 cell = glm::min(glm::ivec3(p), dims_ - 2);
        const std::int32_t candidate = look_.perm.index(cell.x, cell.y, cell.z);
        if (candidate == PermStructure::kNull) {
            ++empty_;
            ++ray_empty_;
            return false;
        }
        if (candidate != current_) {
            record_.touches.push_back({static_cast<std::uint32_t>(candidate), samples_, empty_, 0, cued_});
            samples_ = empty_ = cued_ = 0;
            current_ = candidate;
            ++counts_.cell_fetches;
        }
        ++samples_;
        ++ray_samples_;
        const glm::vec3 fraction = p - glm::vec3(cell);
        return look_.shaded != nullptr ? add_shaded(static_cast<std::uint32_t>(candidate), fraction, p)
                                       : add_classified(static_cast<std::uint32_t>(candidate), fraction, p);
    }

    // A sample the PPs shaded: the record's colour at its density position. PP-shaded records are
    // shaded without the depth cue, which dims only the directly lit part: the GP takes the ambient
    // part from the density's base colour and divides the rest.
    bool add_shaded(std::uint32_t candidate, glm::vec3 fraction, glm::vec3 p) {
        const int at = look_.perm.density_position(fraction, &counts_.carried_lookups);
        const glm::vec4 rgba = look_.shaded->at(candidate, at);
        if (!(rgba.a > 0.0f)) return false;
        glm::vec3 rgb(rgba);
        if (look_.cue) {
            const glm::vec3 ambient = look_.colors.color(look_.perm.density_at(candidate, at)) * look_.lighting.ambient;
            const float divisor =
                look_.lighting.depth_cue_k1 + look_.lighting.depth_cue_k2 * look_.view.depth(p * look_.spacing);
            rgb = ambient + glm::max(rgb - ambient, glm::vec3(0.0f)) / divisor;
            ++cued_;
        }
        return color_.add(glm::clamp(rgb, 0.0f, 1.0f), rgba.a);
    }

    // A sample the GP classifies and shades from the record's quantized density and gradient.
    bool add_classified(std::uint32_t candidate, glm::vec3 fraction, glm::vec3 p) {
        const PermStructure::Sample s = look_.perm.lookup(candidate, fraction, &counts_.carried_lookups);
        const float alpha = look_.classification.opacity(s.value, glm::length(s.gradient));
        if (!(alpha > 0.0f)) return false;
        return color_.add(look_.shader.shade(s.value, s.gradient, p * look_.spacing), alpha);
    }

    const FrameLook& look_;
    glm::ivec3 dims_;
    FrontToBack color_;
    PermCastCounts& counts_;
    RayRecord record_;
    std::int64_t current_ = -1;                         // the cell whose record the ray holds
    std::uint32_t samples_ = 0, empty_ = 0, cued_ = 0;  // since the last fetch
    std::uint64_t ray_samples_ = 0, ray_empty_ = 0;
};

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
    const glm::ivec3 dims = structure_->dims();
    const detail::MarchFrame frame(dims, spacing_, cs.sample_step);
    const PixelRays rays(camera, cs.width, cs.height);
    const ShadingView view = make_shading_view(camera, dims, spacing_);
    const SampleShader shader(colors, lighting, view, spacing_);
    const bool cue = shaded_ != nullptr && lighting.depth_cue_k2 != 0.0f;
    const FrameLook look{*structure_, occupancy_, shaded_, classification, colors,
                         lighting,    view,       shader,  spacing_,       cue};
    const TileGrid grid{settings_.tile_pixels, (cs.width + settings_.tile_pixels - 1) / settings_.tile_pixels, cs.width,
                        cs.height};
    const int tiles = grid.across * ((cs.height + grid.edge - 1) / grid.edge);
    PermFrame out;
    out.image = Image(cs.width, cs.height);
    std::vector<TileResult> results(static_cast<std::size_t>(tiles));
    pp5::parallel_for(0, tiles, [&](int t) {
        TileResult& result = results[static_cast<std::size_t>(t)];
        const ScreenRect rect = grid.rect(t);
        for (int py = rect.y; py < rect.y + rect.height; ++py)
            for (int px = rect.x; px < rect.x + rect.width; ++px) {
                PermRay ray(look, cs, result.counts);
                result.rays.push_back(ray.cast(detail::clip_to_volume(rays.ray(px, py), frame)));
                out.image.at(px, py) = ray.color(cs.background);
            }
    });

    // The recorded work, tile by tile.
    out.work = record_tiles(results, grid, records_ ? (cue ? cued_records_ : records_) : nullptr, shaded_ != nullptr);
    for (const TileResult& result : results) out.counts += result.counts;
    return out;
}

}  // namespace pp5
