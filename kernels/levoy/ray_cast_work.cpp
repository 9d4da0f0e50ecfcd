#include "kernels/levoy/ray_cast_work.h"

#include "kernels/levoy/levoy_costs.h"
#include "kernels/levoy/levoy_renderer.h"

#include <numeric>

namespace pp5 {

TileOrder order_by_tile(const ScreenTiles& tiles, const std::vector<std::uint32_t>& pending) {
    TileOrder order;
    order.first.assign(static_cast<std::size_t>(tiles.count()) + 1, 0);
    for (const std::uint32_t p : pending) ++order.first[static_cast<std::size_t>(tiles.of(p)) + 1];
    std::partial_sum(order.first.begin(), order.first.end(), order.first.begin());
    order.pixels.resize(pending.size());
    std::vector<std::uint32_t> next = order.first;
    for (const std::uint32_t p : pending) order.pixels[next[static_cast<std::size_t>(tiles.of(p))]++] = p;
    return order;
}

std::vector<std::uint32_t> tests_per_tile(const ScreenTiles& tiles, const AdaptiveRefinement& refinement) {
    std::vector<std::uint32_t> tests(static_cast<std::size_t>(tiles.count()), 0);
    for (const std::uint32_t corner : refinement.tested_squares()) ++tests[static_cast<std::size_t>(tiles.of(corner))];
    return tests;
}

// One ray as an item: a step per block look-up (its ray setup in the first), then the rest.
void RayWorkRecorder::add_ray(const CastBatch& batch, const RayWork& ray) {
    GpItem item{static_cast<std::uint32_t>(job_.steps.size()), 0};
    bool setup = true;
    const auto add_step = [&](std::uint32_t samples, std::uint32_t pyramid_steps, std::uint32_t block) {
        GpStep step{static_cast<std::uint32_t>(job_.ops.size()), 0, block};
        if (setup) append_ops(job_.ops, kRaySetup, 1);
        setup = false;
        append_ops(job_.ops, kSample, samples);
        append_ops(job_.ops, kPyramidStep, pyramid_steps);
        step.op_count = static_cast<std::uint32_t>(job_.ops.size()) - step.first_op;
        job_.steps.push_back(step);
        ++item.step_count;
    };
    for (std::uint32_t i = 0; i < ray.touch_count; ++i) {
        const BlockTouch& touch = batch.touches[ray.first_touch + i];
        add_step(touch.samples, touch.pyramid_steps, touch.block);
    }
    if (setup || ray.tail_samples > 0 || ray.tail_pyramid_steps > 0)
        add_step(ray.tail_samples, ray.tail_pyramid_steps, kNoFetch);
    job_.items.push_back(item);
    ++counts_.rays;
    counts_.samples += ray.samples;
    counts_.samples_skipped += ray.samples_skipped;
    counts_.pyramid_steps += ray.pyramid_steps;
    if (ray.terminated) ++counts_.rays_terminated;
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
