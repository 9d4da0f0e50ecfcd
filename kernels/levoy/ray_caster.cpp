#include "kernels/levoy/ray_caster.h"

#include "scene/reference/ray_march.h"
#include "scene/reference/trilinear.h"
#include "scene/render/front_to_back.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pp5 {

RayCaster::RayCaster(const ShadedCodes& volume, const BinaryPyramid& pyramid, const VoxelBlocks& blocks,
                     const Camera& camera, const RayCastSettings& settings)
    : volume_(volume),
      pyramid_(pyramid),
      blocks_(blocks),
      settings_(settings),
      rays_((validate_camera(camera), camera), settings.width, settings.height) {
    if (pyramid.levels() == 0 || pyramid.cell_dims(0) != volume.dims() - 1)
        throw std::invalid_argument("ray caster: pyramid of another volume");
    if (!(settings.sample_step > 0.0f) || settings.width < 1 || settings.height < 1)
        throw std::invalid_argument("ray caster: bad image size or sample step");
}

namespace {

// The t at which a ray leaves the box [lo, hi) (voxel coordinates).
float exit_of_box(const detail::ClippedRay& ray, glm::vec3 lo, glm::vec3 hi) {
    float t = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (ray.direction[a] > 0.0f) t = std::min(t, (hi[a] - ray.origin[a]) * ray.inverse_direction[a]);
        else if (ray.direction[a] < 0.0f) t = std::min(t, (lo[a] - ray.origin[a]) * ray.inverse_direction[a]);
    }
    return t;
}

}  // namespace

void RayCaster::cast_one(std::uint32_t pixel, std::uint32_t start, glm::vec4& color, RayWork& work,
                         std::vector<BlockTouch>& touches) const {
    const int px = static_cast<int>(pixel % static_cast<std::uint32_t>(settings_.width));
    const int py = static_cast<int>(pixel / static_cast<std::uint32_t>(settings_.width));
    const detail::MarchFrame frame(volume_.dims(), volume_.spacing(), settings_.sample_step);
    FrontToBack ray_color(settings_.sample_step, settings_.early_termination ? settings_.termination_opacity : 2.0f);
    work.pixel = pixel;
    work.first_touch = static_cast<std::uint32_t>(touches.size());
    const auto ray = detail::clip_to_volume(rays_.ray(px, py), frame);
    if (!ray) {
        color = ray_color.over(settings_.background);
        return;
    }
    work.hit = true;
    const detail::Grid grid(volume_.dims());
    const glm::u8vec4* narrow_codes = volume_.narrow() ? volume_.narrow_codes() : nullptr;
    const glm::u16vec4* wide_codes = volume_.wide_codes();
    const glm::vec4 code_max = volume_.code_max();
    // A leap stops short of the empty cell's exit by a little more than the error in a sample's
    // position, so no sample past the exit is ever passed over; one that falls short is tested again.
    const float fastest =
        std::max({std::abs(ray->direction.x), std::abs(ray->direction.y), std::abs(ray->direction.z)});
    const float margin = 2e-3f / fastest;
    const int top = pyramid_.levels() - 1;

    std::uint32_t samples_since = 0;
    std::uint32_t steps_since = 0;
    std::uint32_t current_block = std::numeric_limits<std::uint32_t>::max();
    bool first_found = false;
    int k = std::min(static_cast<int>(start), ray->sample_count);
    work.samples_skipped = static_cast<std::uint32_t>(k);
    while (k < ray->sample_count) {
        const detail::Cell cell = grid.cell(ray->position(k));
        if (settings_.pyramid_skipping) {
            ++steps_since;
            ++work.pyramid_steps;
            if (!pyramid_.occupied(0, cell.corner)) {
                // The climb checks levels 1 up to the first occupied one (or the top), and leaps
                // across the box of the last empty level.
                const int level = top > 0 ? pyramid_.empty_levels_above(cell.corner) : 0;
                const auto checks = static_cast<std::uint32_t>(std::min(level + 1, top));
                steps_since += checks;
                work.pyramid_steps += checks;
                const glm::ivec3 box = (cell.corner >> level) << level;
                const float t_exit = exit_of_box(*ray, glm::vec3(box), glm::vec3(box + (1 << level)));
                const int next = std::max(k + 1, ray->samples_before(t_exit - margin));
                work.samples_skipped += static_cast<std::uint32_t>(next - k);
                k = next;
                continue;
            }
        }
        if (!first_found) {
            first_found = true;
            work.first_sample = static_cast<std::uint32_t>(k);
        }
        const std::uint32_t block = blocks_.block_of(cell.corner);
        if (block != current_block) {
            touches.push_back(BlockTouch{block, samples_since, steps_since});
            samples_since = 0;
            steps_since = 0;
            current_block = block;
        }
        const glm::vec4 s = narrow_codes != nullptr ? grid.interpolate_codes(cell, narrow_codes, code_max)
                                                    : grid.interpolate_codes(cell, wide_codes, code_max);
        ++samples_since;
        ++work.samples;
        if (ray_color.add(glm::vec3(s), s.a)) {
            work.terminated = true;
            break;
        }
        ++k;
    }
    if (!first_found) work.first_sample = static_cast<std::uint32_t>(ray->sample_count);
    work.tail_samples = samples_since;
    work.tail_pyramid_steps = steps_since;
    work.touch_count = static_cast<std::uint32_t>(touches.size()) - work.first_touch;
    color = ray_color.over(settings_.background);
}

CastBatch RayCaster::cast(std::span<const std::uint32_t> pixels, std::span<const std::uint32_t> start_samples) const {
    const std::size_t image_pixels =
        static_cast<std::size_t>(settings_.width) * static_cast<std::size_t>(settings_.height);
    if (!start_samples.empty() && start_samples.size() != image_pixels)
        throw std::invalid_argument("ray caster: a depth buffer of another image size");
    CastBatch batch;
    batch.colors.resize(pixels.size());
    batch.rays.resize(pixels.size());
    // Rays are cast in fixed chunks, each with its own touch list, joined in order afterwards: the
    // same records at any thread count.
    constexpr std::size_t kChunk = 256;
    const std::size_t chunks = (pixels.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<BlockTouch>> chunk_touches(chunks);
    pp5::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
            auto& touches = chunk_touches[c];
            for (std::size_t i = c * kChunk; i < std::min(pixels.size(), (c + 1) * kChunk); ++i) {
                if (pixels[i] >= image_pixels) throw std::out_of_range("ray caster: pixel outside the image");
                const std::uint32_t start = start_samples.empty() ? 0 : start_samples[pixels[i]];
                cast_one(pixels[i], start, batch.colors[i], batch.rays[i], touches);
            }
        }
    });
    std::vector<std::size_t> chunk_offset(chunks + 1, 0);
    for (std::size_t c = 0; c < chunks; ++c) chunk_offset[c + 1] = chunk_offset[c] + chunk_touches[c].size();
    if (chunk_offset[chunks] >= std::numeric_limits<std::uint32_t>::max())
        throw std::length_error("ray caster: too many block look-ups in one batch");
    batch.touches.resize(chunk_offset[chunks]);
    pp5::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        const auto offset = static_cast<std::uint32_t>(chunk_offset[c]);
        for (std::size_t i = c * kChunk; i < std::min(pixels.size(), (c + 1) * kChunk); ++i)
            batch.rays[i].first_touch += offset;
        std::copy(chunk_touches[c].begin(), chunk_touches[c].end(),
                  batch.touches.begin() + static_cast<std::ptrdiff_t>(offset));
    });
    return batch;
}

}  // namespace pp5
