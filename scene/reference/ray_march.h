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

// An Amanatides-Woo walk over an occupancy grid's blocks, in voxel coordinates: the block the ray is
// in, and the t at which it crosses each next face.
class BlockWalk {
public:
    static constexpr float kBlock = static_cast<float>(OccupancyGrid::kBlockSize);

    BlockWalk(const ClippedRay& ray, const OccupancyGrid& grid)
        : ray_(ray), grid_(grid), blocks_(grid.block_dims()), distances_(grid.distances()) {
        const std::ptrdiff_t axis_stride[3] = {1, blocks_.x, static_cast<std::ptrdiff_t>(blocks_.x) * blocks_.y};
        for (int a = 0; a < 3; ++a) {
            step_dir_[a] = ray.direction[a] > 0.0f ? 1 : (ray.direction[a] < 0.0f ? -1 : 0);
            index_step_[a] = step_dir_[a] * axis_stride[a];
            if (step_dir_[a] != 0) t_delta_[a] = kBlock * std::abs(ray.inverse_direction[a]);
        }
        enter(glm::clamp(block_at(ray.t_enter), glm::ivec3(0), blocks_ - 1));
    }

    // The current block's distance, in blocks, from the nearest occupied one (0: it is occupied).
    int distance() const { return distances_[index_]; }

    // Where the ray leaves the empty cube [block - r, block + r].
    float cube_exit(int r) const {
        float t_cube = std::numeric_limits<float>::infinity();
        for (int a = 0; a < 3; ++a) {
            if (step_dir_[a] == 0) continue;
            const int face = step_dir_[a] > 0 ? block_[a] + r + 1 : block_[a] - r;
            t_cube = std::min(t_cube, face_t(a, face));
        }
        return t_cube;
    }

    // Moves to the block the ray is in at t; false when that lies outside the grid.
    bool jump_to(float t) {
        const glm::ivec3 next = block_at(t);
        if (!glm::all(glm::greaterThanEqual(next, glm::ivec3(0))) || !glm::all(glm::lessThan(next, blocks_)))
            return false;
        enter(next);
        return true;
    }

    // The face the ray crosses next: its axis, and the t where it crosses (without branches, the
    // choice being unpredictable).
    float nearest_face(int& axis) const {
        const int y_first = t_next_.y < t_next_.x ? 1 : 0;
        const float t_xy = std::min(t_next_.x, t_next_.y);
        axis = t_next_.z < t_xy ? 2 : y_first;
        return std::min(t_xy, t_next_.z);
    }

    // Steps through the nearest face along axis; false when that leaves the grid.
    bool step(int axis) {
        block_[axis] += step_dir_[axis];
        if (block_[axis] < 0 || block_[axis] >= blocks_[axis]) return false;
        index_ += index_step_[axis];
        t_next_[axis] += t_delta_[axis];
        return true;
    }

private:
    float face_t(int axis, int face) const {
        return (static_cast<float>(face) * kBlock - ray_.origin[axis]) * ray_.inverse_direction[axis];
    }
    glm::ivec3 block_at(float t) const { return glm::ivec3(glm::floor((ray_.origin + t * ray_.direction) / kBlock)); }
    void enter(glm::ivec3 b) {
        block_ = b;
        index_ = static_cast<std::ptrdiff_t>(grid_.block_index(b));
        for (int a = 0; a < 3; ++a)
            if (step_dir_[a] != 0) t_next_[a] = face_t(a, step_dir_[a] > 0 ? b[a] + 1 : b[a]);
    }

    const ClippedRay& ray_;
    const OccupancyGrid& grid_;
    glm::ivec3 blocks_;
    const std::uint8_t* distances_;
    glm::ivec3 step_dir_{0};
    std::ptrdiff_t index_step_[3] = {0, 0, 0};
    glm::vec3 t_delta_{std::numeric_limits<float>::infinity()};
    glm::ivec3 block_{0};
    std::ptrdiff_t index_ = 0;
    glm::vec3 t_next_{std::numeric_limits<float>::infinity()};
};

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

    // Samples are placed in blocks only on entering an occupied block, so empty blocks cost a few
    // compares each; an empty block at distance D >= 2 from occupied ones lies in an empty cube of
    // radius D-1 blocks, which the ray leaves in one leap (the samples inside it are skipped exactly
    // like those of single empty blocks).
    BlockWalk walk(ray, *grid);
    const float t_last = ray.t_of(ray.sample_count - 1);
    int k = 0;                 // the first sample not yet visited or skipped
    float t_in = ray.t_enter;  // where the ray entered the current block
    float t_out = t_in;        // where it leaves it (or the leap ends)
    bool in_occupied = false;
    for (;;) {
        const int distance = walk.distance();
        in_occupied = distance == 0;
        if (distance >= 2) {
            const float t_cube = walk.cube_exit(distance - 1);
            if (t_cube > t_in) {  // always, barring rounding; otherwise take a single step below
                t_out = t_cube;
                if (t_cube > t_last || !walk.jump_to(t_cube)) break;
                t_in = t_cube;
                continue;
            }
        }
        int axis = 0;
        t_out = walk.nearest_face(axis);
        if (in_occupied) {
            const int k_begin = std::max(k, ray.samples_before(t_in));
            counts.skipped += static_cast<std::uint64_t>(k_begin - k);
            const int k_end = std::max(k_begin, ray.samples_before(t_out));
            if (!visit_range(k_begin, k_end)) return counts;
            k = k_end;
        }
        if (t_out > t_last) break;  // the last sample lies in this block
        if (!walk.step(axis)) break;
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
