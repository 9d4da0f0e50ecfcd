#pragma once
// Internal to the reference renderer: where a ray meets the volume, where its samples lie, and the
// walk over the occupancy grid that skips empty blocks without moving any sample.
//
// Samples sit on one grid per ray whatever is skipped: t_k = t_enter + (k + 0.5) step for
// k in [0, sample_count), t in world units along the unit ray, t_enter where the ray enters the box
// (or 0 when it starts inside). sample_count = floor((t_exit - t_enter) / step + 1/2): the intervals
// whose centres lie inside the box. A sample's position is always computed from k alone, so the
// skipping walk and the plain loop evaluate bit-identical positions.

#include "scene/reference/composite.h"
#include "scene/reference/occupancy_grid.h"
#include "scene/render/camera.h"

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

namespace pp5::detail {

// The volume's box in voxel coordinates and the sampling step.
struct MarchFrame {
    glm::vec3 inverse_spacing{1.0f};
    glm::vec3 upper{0.0f};   // dims - 1: the box is [0, upper] in voxel coordinates
    float step = 1.0f;       // world units between samples
    bool degenerate = true;  // a dimension of one voxel: the box has no volume, no ray meets it

    MarchFrame(glm::ivec3 dims, glm::vec3 spacing, float sample_step_voxels)
        : inverse_spacing(1.0f / spacing),
          upper(glm::vec3(dims - 1)),
          step(sample_step_voxels * std::min({spacing.x, spacing.y, spacing.z})),
          degenerate(dims.x < 2 || dims.y < 2 || dims.z < 2) {}
};

// A ray clipped to the box: position(k) in voxel coordinates.
struct ClippedRay {
    glm::vec3 origin{0.0f};             // voxel coordinates at t = 0
    glm::vec3 direction{0.0f};          // voxel coordinates per world unit
    glm::vec3 inverse_direction{0.0f};  // 1 / direction (infinite along an axis the ray does not move on)
    float t_enter = 0.0f;
    float step = 1.0f;
    float inverse_step = 1.0f;
    int sample_count = 0;

    float t_of(int k) const { return t_enter + (static_cast<float>(k) + 0.5f) * step; }
    glm::vec3 position(int k) const { return origin + t_of(k) * direction; }
    // The number of samples with t_k < t: the first sample at or after t. (Only used to split samples
    // among blocks; a rounding error here moves a sample by a hair across a block face, which the
    // occupancy test's margin covers.)
    int samples_before(float t) const {
        const float k = std::ceil((t - t_enter) * inverse_step - 0.5f);
        if (!(k > 0.0f)) return 0;
        return k >= static_cast<float>(sample_count) ? sample_count : static_cast<int>(k);
    }
};

// Slab test against [0, upper] in voxel coordinates. No value when the ray misses or takes no sample.
inline std::optional<ClippedRay> clip_to_volume(const Ray& ray, const MarchFrame& frame) {
    if (frame.degenerate) return std::nullopt;
    ClippedRay clipped;
    clipped.origin = ray.origin * frame.inverse_spacing;
    clipped.direction = ray.direction * frame.inverse_spacing;
    clipped.inverse_direction = 1.0f / clipped.direction;
    clipped.step = frame.step;
    clipped.inverse_step = 1.0f / frame.step;
    float t_near = 0.0f;  // nothing behind the eye (or the parallel view's image plane) is seen
    float t_far = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
        const float o = clipped.origin[a];
        if (clipped.direction[a] == 0.0f) {
            if (o < 0.0f || o > frame.upper[a]) return std::nullopt;
            continue;
        }
        float t0 = (0.0f - o) * clipped.inverse_direction[a];
        float t1 = (frame.upper[a] - o) * clipped.inverse_direction[a];
        if (t0 > t1) std::swap(t0, t1);
        t_near = std::max(t_near, t0);
        t_far = std::min(t_far, t1);
    }
    if (!(t_far > t_near)) return std::nullopt;
    const float count = std::floor((t_far - t_near) * clipped.inverse_step + 0.5f);
    if (!(count >= 1.0f)) return std::nullopt;
    clipped.t_enter = t_near;
    clipped.sample_count = count >= 2e9f ? 2000000000 : static_cast<int>(count);
    return clipped;
}

struct MarchCounts {
    std::uint64_t samples = 0;  // samples evaluated
    std::uint64_t skipped = 0;  // samples in empty blocks, not evaluated
    bool terminated = false;    // the visitor stopped the ray
};

// Adds one marched ray's counts to a compositor's work counters.
inline void tally(CompositeStats& stats, const MarchCounts& marched) {
    stats.samples += marched.samples;
    stats.samples_skipped += marched.skipped;
    if (marched.terminated) ++stats.rays_terminated;
}

// Calls visit(k, position) for the ray's samples in order, until it returns true (the ray is opaque).
// With an occupancy grid, samples in empty blocks are counted and not visited.
template <class Visit>
MarchCounts march(const ClippedRay& ray, const OccupancyGrid* grid, Visit&& visit) {
    MarchCounts counts;
    auto visit_range = [&](int k_begin, int k_end) {
        for (int k = k_begin; k < k_end; ++k) {
            ++counts.samples;
            if (visit(k, ray.position(k))) {
                counts.terminated = true;
                return false;
            }
        }
        return true;
    };
    if (grid == nullptr) {
        visit_range(0, ray.sample_count);
        return counts;
    }

    // Amanatides-Woo walk over blocks, in voxel coordinates. Samples are placed in blocks only on
    // entering an occupied block, so empty blocks cost a few compares each; an empty block at distance
    // D >= 2 from occupied ones lies in an empty cube of radius D-1 blocks, which the ray leaves in one
    // leap (the samples inside it are skipped exactly like those of single empty blocks).
    constexpr float kBlock = static_cast<float>(OccupancyGrid::kBlockSize);
    const glm::ivec3 blocks = grid->block_dims();
    const std::uint8_t* distances = grid->distances();
    const std::ptrdiff_t axis_stride[3] = {1, blocks.x, static_cast<std::ptrdiff_t>(blocks.x) * blocks.y};
    glm::ivec3 step_dir{0};
    std::ptrdiff_t index_step[3] = {0, 0, 0};
    glm::vec3 t_delta{std::numeric_limits<float>::infinity()};
    for (int a = 0; a < 3; ++a) {
        step_dir[a] = ray.direction[a] > 0.0f ? 1 : (ray.direction[a] < 0.0f ? -1 : 0);
        index_step[a] = step_dir[a] * axis_stride[a];
        if (step_dir[a] != 0) t_delta[a] = kBlock * std::abs(ray.inverse_direction[a]);
    }
    glm::ivec3 block{0};
    std::ptrdiff_t index = 0;
    glm::vec3 t_next{std::numeric_limits<float>::infinity()};
    // Places the walk in a block: its index and the t at which the ray crosses each next face.
    auto enter = [&](glm::ivec3 b) {
        block = b;
        index = static_cast<std::ptrdiff_t>(grid->block_index(b));
        for (int a = 0; a < 3; ++a) {
            if (step_dir[a] == 0) continue;
            const int face = step_dir[a] > 0 ? b[a] + 1 : b[a];
            t_next[a] = (static_cast<float>(face) * kBlock - ray.origin[a]) * ray.inverse_direction[a];
        }
    };
    auto block_at = [&](float t) { return glm::ivec3(glm::floor((ray.origin + t * ray.direction) / kBlock)); };
    auto inside = [&](glm::ivec3 b) {
        return glm::all(glm::greaterThanEqual(b, glm::ivec3(0))) && glm::all(glm::lessThan(b, blocks));
    };
    enter(glm::clamp(block_at(ray.t_enter), glm::ivec3(0), blocks - 1));
    const float t_last = ray.t_of(ray.sample_count - 1);

    int k = 0;                 // the first sample not yet visited or skipped
    float t_in = ray.t_enter;  // where the ray entered the current block
    float t_out = t_in;        // where it leaves it (or the leap ends)
    bool in_occupied = false;
    for (;;) {
        const int distance = distances[index];
        in_occupied = distance == 0;
        if (distance >= 2) {
            // Leave the empty cube [block - r, block + r], r = distance - 1.
            const int r = distance - 1;
            float t_cube = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a) {
                if (step_dir[a] == 0) continue;
                const int face = step_dir[a] > 0 ? block[a] + r + 1 : block[a] - r;
                t_cube =
                    std::min(t_cube, (static_cast<float>(face) * kBlock - ray.origin[a]) * ray.inverse_direction[a]);
            }
            if (t_cube > t_in) {  // always, barring rounding; otherwise take a single step below
                t_out = t_cube;
                if (t_cube > t_last) break;
                const glm::ivec3 next = block_at(t_cube);
                if (!inside(next)) break;
                t_in = t_cube;
                enter(next);
                continue;
            }
        }
        // The nearest face, without branches (the choice is unpredictable).
        const int y_first = t_next.y < t_next.x ? 1 : 0;
        const float t_xy = std::min(t_next.x, t_next.y);
        const int axis = t_next.z < t_xy ? 2 : y_first;
        t_out = std::min(t_xy, t_next.z);
        if (in_occupied) {
            const int k_begin = std::max(k, ray.samples_before(t_in));
            counts.skipped += static_cast<std::uint64_t>(k_begin - k);
            const int k_end = std::max(k_begin, ray.samples_before(t_out));
            if (!visit_range(k_begin, k_end)) return counts;
            k = k_end;
        }
        if (t_out > t_last) break;  // the last sample lies in this block
        block[axis] += step_dir[axis];
        if (block[axis] < 0 || block[axis] >= blocks[axis]) break;
        index += index_step[axis];
        t_next[axis] += t_delta[axis];
        t_in = t_out;
    }
    if (!in_occupied) {
        const int k_end = std::max(k, ray.samples_before(t_out));
        counts.skipped += static_cast<std::uint64_t>(k_end - k);
        k = k_end;
    }
    // Rounding can let the walk leave the grid a hair before the last sample: those samples are
    // evaluated, never skipped.
    visit_range(k, ray.sample_count);
    return counts;
}

}  // namespace pp5::detail
