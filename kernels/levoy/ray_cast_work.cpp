#include "kernels/levoy/ray_cast_work.h"

#include "kernels/levoy/levoy_costs.h"
#include "kernels/levoy/levoy_renderer.h"
#include "sim/core/parallel.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace pp5 {

TileOrder order_by_tile(const ScreenTiles& tiles, const std::vector<std::uint32_t>& pending) {
    if (!std::is_sorted(pending.begin(), pending.end()))
        throw std::invalid_argument("ray casting: the pending pixels are not in row-major order");
    // Row-major, so each row of tiles is a run of the list: the rows of tiles are sorted in parallel,
    // each counting its tiles' pixels and then placing them.
    const auto rows = static_cast<std::size_t>(tiles.down);
    const auto across = static_cast<std::size_t>(tiles.across);
    std::vector<std::size_t> row_start(rows + 1, pending.size());
    for (std::size_t r = 0; r < rows; ++r) {
        const auto first_pixel = static_cast<std::uint32_t>(r * static_cast<std::size_t>(tiles.edge) *
                                                            static_cast<std::size_t>(tiles.width));
        row_start[r] =
            static_cast<std::size_t>(std::lower_bound(pending.begin(), pending.end(), first_pixel) - pending.begin());
    }
    TileOrder order;
    order.first.assign(static_cast<std::size_t>(tiles.count()) + 1, 0);
    pp5::parallel_for(std::size_t{0}, rows, [&](std::size_t r) {
        for (std::size_t i = row_start[r]; i < row_start[r + 1]; ++i)
            ++order.first[static_cast<std::size_t>(tiles.of(pending[i])) + 1];
    });
    std::partial_sum(order.first.begin(), order.first.end(), order.first.begin());
    order.pixels.resize(pending.size());
    pp5::parallel_for(std::size_t{0}, rows, [&](std::size_t r) {
        std::vector<std::uint32_t> next(order.first.begin() + static_cast<std::ptrdiff_t>(r * across),
                                        order.first.begin() + static_cast<std::ptrdiff_t>((r + 1) * across));
        for (std::size_t i = row_start[r]; i < row_start[r + 1]; ++i)
            order.pixels[next[static_cast<std::size_t>(tiles.of(pending[i])) - r * across]++] = pending[i];
    });
    return order;
}

std::vector<std::uint32_t> tests_per_tile(const ScreenTiles& tiles, const AdaptiveRefinement& refinement) {
    std::vector<std::uint32_t> tests(static_cast<std::size_t>(tiles.count()), 0);
    for (const std::uint32_t corner : refinement.tested_squares()) ++tests[static_cast<std::size_t>(tiles.of(corner))];
    return tests;
}

namespace {

// A ray's steps: one per block look-up, then one for the work after the last (or for its setup alone).
std::uint32_t steps_of(const RayWork& ray) {
    const bool tail = ray.touch_count == 0 || ray.tail_samples > 0 || ray.tail_pyramid_steps > 0;
    return ray.touch_count + (tail ? 1u : 0u);
}

// A step's operations: the ray's setup (its first step), its samples and its pyramid steps, each when
// there are any.
std::uint32_t ops_of(bool setup, std::uint32_t samples, std::uint32_t pyramid_steps) {
    return (setup ? 1u : 0u) + (samples > 0 ? 1u : 0u) + (pyramid_steps > 0 ? 1u : 0u);
}

GpOp* write_ops(GpOp* out, bool setup, std::uint32_t samples, std::uint32_t pyramid_steps) {
    if (setup) *out++ = GpOp{kRaySetup, 1};
    if (samples > 0) *out++ = GpOp{kSample, samples};
    if (pyramid_steps > 0) *out++ = GpOp{kPyramidStep, pyramid_steps};
    return out;
}

// Where one tile's share of a pass starts in each of the phase's lists, and how long it is.
struct TileSpan {
    std::uint64_t items = 0, steps = 0, ops = 0, tasks = 0;
};

}  // namespace

std::uint64_t RayWorkRecorder::add_pass(std::uint32_t pass, const CastBatch& batch, const TileOrder& order,
                                        std::span<const std::uint32_t> tests, std::span<const std::uint32_t> filled) {
    const auto tiles = static_cast<std::size_t>(tiles_.count());
    // First what each tile adds, then (after a running sum) each tile writes its own part of the lists.
    std::vector<TileSpan> size(tiles);
    std::vector<RayCastCounts> counts(tiles);
    pp5::parallel_for(std::size_t{0}, tiles, [&](std::size_t t) {
        TileSpan& n = size[t];
        RayCastCounts& c = counts[t];
        for (std::uint32_t r = order.first[t]; r < order.first[t + 1]; ++r) {
            const RayWork& ray = batch.rays[r];
            n.steps += steps_of(ray);
            for (std::uint32_t i = 0; i < ray.touch_count; ++i) {
                const BlockTouch& touch = batch.touches[ray.first_touch + i];
                n.ops += ops_of(i == 0, touch.samples, touch.pyramid_steps);
            }
            if (steps_of(ray) > ray.touch_count)
                n.ops += ops_of(ray.touch_count == 0, ray.tail_samples, ray.tail_pyramid_steps);
            ++c.rays;
            c.samples += ray.samples;
            c.samples_skipped += ray.samples_skipped;
            c.pyramid_steps += ray.pyramid_steps;
            if (ray.terminated) ++c.rays_terminated;
        }
        n.items = order.first[t + 1] - order.first[t];
        if (n.items > 0 || tests[t] > 0) n.tasks = 1;
        n.ops += tests[t] > 0 ? 1 : 0;
        if (n.items > 0) {
            n.ops += filled[t] > 0 ? 1 : 0;
            c.pixels_filled = filled[t];
        }
    });
    std::vector<TileSpan> first(tiles);
    TileSpan end{job_.items.size(), job_.steps.size(), job_.ops.size(), job_.tasks.size()};
    for (std::size_t t = 0; t < tiles; ++t) {
        first[t] = end;
        end.items += size[t].items;
        end.steps += size[t].steps;
        end.ops += size[t].ops;
        end.tasks += size[t].tasks;
    }
    if (end.items > std::numeric_limits<std::uint32_t>::max() ||
        end.steps > std::numeric_limits<std::uint32_t>::max() || end.ops > std::numeric_limits<std::uint32_t>::max())
        throw std::length_error("ray casting: too much work for one frame's record");
    job_.items.resize(end.items);
    job_.steps.resize(end.steps);
    job_.ops.resize(end.ops);
    job_.tasks.resize(end.tasks);
    pp5::parallel_for(std::size_t{0}, tiles, [&](std::size_t t) {
        auto item = static_cast<std::uint32_t>(first[t].items);
        auto step = static_cast<std::uint32_t>(first[t].steps);
        GpOp* const ops = job_.ops.data();
        GpOp* op = ops + first[t].ops;
        const auto at = [&] { return static_cast<std::uint32_t>(op - ops); };
        for (std::uint32_t r = order.first[t]; r < order.first[t + 1]; ++r) {
            const RayWork& ray = batch.rays[r];
            job_.items[item++] = GpItem{step, steps_of(ray)};
            for (std::uint32_t i = 0; i < ray.touch_count; ++i) {
                const BlockTouch& touch = batch.touches[ray.first_touch + i];
                const std::uint32_t from = at();
                op = write_ops(op, i == 0, touch.samples, touch.pyramid_steps);
                job_.steps[step++] = GpStep{from, at() - from, touch.block};
            }
            if (steps_of(ray) > ray.touch_count) {
                const std::uint32_t from = at();
                op = write_ops(op, ray.touch_count == 0, ray.tail_samples, ray.tail_pyramid_steps);
                job_.steps[step++] = GpStep{from, at() - from, kNoFetch};
            }
        }
        if (size[t].tasks == 0) return;
        GpTask& task = job_.tasks[first[t].tasks];
        task = GpTask{};
        task.group = pass;
        task.key = key_of(static_cast<int>(t));
        task.screen = tiles_.rect(static_cast<int>(t));
        task.first_item = static_cast<std::uint32_t>(first[t].items);
        task.item_count = static_cast<std::uint32_t>(size[t].items);
        task.first_op = at();
        if (tests[t] > 0) *op++ = GpOp{kRefinementTest, tests[t]};
        task.op_count = at() - task.first_op;
        task.first_finish_op = at();
        if (task.item_count > 0) {  // a tile that cast nothing sends nothing
            if (filled[t] > 0) *op++ = GpOp{kPixelFill, filled[t]};
            task.pixels = tiles_.pixels_in(static_cast<int>(t));
        }
        task.finish_op_count = at() - task.first_finish_op;
    });
    std::uint64_t samples = 0;
    for (const RayCastCounts& c : counts) {
        counts_.rays += c.rays;
        counts_.samples += c.samples;
        counts_.samples_skipped += c.samples_skipped;
        counts_.pyramid_steps += c.pyramid_steps;
        counts_.rays_terminated += c.rays_terminated;
        counts_.pixels_filled += c.pixels_filled;
        samples += c.samples;
    }
    return samples;
}

// Tile t's task of a pass: its refinement tests, the rays added since `first_item`, then the pixels
// it fills in and sends. A task with nothing to do is left out.
void RayWorkRecorder::add_task(std::uint32_t pass, int t, std::uint32_t first_item, std::uint32_t tests,
                               std::uint32_t filled) {
    GpTask task;
    task.group = pass;
    task.key = key_of(t);
    task.screen = tiles_.rect(t);
    task.first_item = first_item;
    task.item_count = static_cast<std::uint32_t>(job_.items.size()) - first_item;
    task.first_op = static_cast<std::uint32_t>(job_.ops.size());
    append_ops(job_.ops, kRefinementTest, tests);
    task.op_count = static_cast<std::uint32_t>(job_.ops.size()) - task.first_op;
    task.first_finish_op = static_cast<std::uint32_t>(job_.ops.size());
    if (task.item_count > 0) {  // a tile that cast nothing sends nothing
        append_ops(job_.ops, kPixelFill, filled);
        task.pixels = tiles_.pixels_in(t);
        counts_.pixels_filled += filled;
    }
    task.finish_op_count = static_cast<std::uint32_t>(job_.ops.size()) - task.first_finish_op;
    if (task.item_count > 0 || tests > 0) job_.tasks.push_back(task);
}

}  // namespace pp5
