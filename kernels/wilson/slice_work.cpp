#include "kernels/wilson/slice_frame_builder.h"

#include "kernels/wilson/wilson_costs.h"

#include <algorithm>
#include <memory>

namespace pp5::slicing {

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

}  // namespace

struct FrameBuilder::Batch {
    std::uint64_t bits = kHeaderBits;
    std::uint32_t setups = 0;  // regions whose slice setup it carries
    std::uint32_t runs = 0;    // quads or points (or blocks) drawn from it
    std::uint64_t write_words = 0;
};

void FrameBuilder::record_work() {
    GpPhase& work = frame.work;
    work.groups = 1;
    work.assignment = TaskAssignment::Static;  // points live in the memory of the GP that owns their brick
    work.blocks = texel_blocks();
    const auto add_program = [&](PpProgram program) {
        work.region_programs.push_back(std::move(program));
        return static_cast<std::uint32_t>(work.region_programs.size() - 1);
    };
    program_.setup = add_program(programs_.setup(projection.perspective()));
    program_.quad = add_program(programs_.quad());
    program_.composite = add_program(programs_.composite());
    program_.point = add_program(gp_sheets ? programs_.block_over() : programs_.point());
    program_.readout = add_program(programs_.readout());
    work.regions.resize(static_cast<std::size_t>(machine_.renderers));

    std::size_t next_point = 0;
    for (std::uint32_t l = 0; l < layers.size(); ++l) {
        if (layers[l].kind == LayerKind::Plane) record_slice(l);
        else next_point = record_slab(l, next_point);
    }
    record_readout();
}

// A brick's texels and the one-texel apron its cells reach into on the high sides.
std::shared_ptr<const BlockDirectory> FrameBuilder::texel_blocks() const {
    const std::size_t brick_count =
        static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y) * static_cast<std::size_t>(bricks_.z);
    std::vector<std::uint32_t> first_part{0};
    std::vector<BlockPart> parts;
    std::uint32_t largest = 1;
    for (std::size_t brick = 0; brick < brick_count; ++brick) {
        const glm::ivec3 bc(
            static_cast<int>(brick % static_cast<std::size_t>(bricks_.x)),
            static_cast<int>((brick / static_cast<std::size_t>(bricks_.x)) % static_cast<std::size_t>(bricks_.y)),
            static_cast<int>(brick / (static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y))));
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
    return std::make_shared<const BlockDirectory>(std::uint64_t{largest} * kCachedTexelBits, kUnitBits,
                                                  std::move(first_part), std::move(parts));
}

GpTask FrameBuilder::begin_task(std::uint32_t brick, bool fetch) {
    GpPhase& work = frame.work;
    GpTask task;
    task.key = brick;
    task.first_item = static_cast<std::uint32_t>(work.items.size());
    task.item_count = 1;
    work.items.push_back(GpItem{static_cast<std::uint32_t>(work.steps.size()), 1});
    work.steps.push_back(GpStep{0, 0, fetch ? brick : kNoFetch});
    task.first_finish_op = static_cast<std::uint32_t>(work.ops.size());
    return task;
}

void FrameBuilder::end_task(GpTask& task, const std::map<std::uint32_t, Batch>& batches, std::uint32_t program,
                            std::vector<bool>* setup_sent, const std::vector<std::uint32_t>* setup_runs) {
    GpPhase& work = frame.work;
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
            steps.push_back(RegionStep{index, program_.setup, (*setup_runs)[renderer], 0});
        }
        steps.push_back(RegionStep{index, program, batch.runs, batch.write_words});
        ++counts.batches;
        counts.batch_words += (batch.bits + 31) / 32;
    }
    task.batch_count = static_cast<std::uint32_t>(batches.size());
    work.tasks.push_back(task);
    ++counts.tasks;
}

void FrameBuilder::record_slice(std::uint32_t l) {
    GpPhase& work = frame.work;
    const std::size_t q0 = first_quad_of_layer[l], q1 = first_quad_of_layer[l + 1];
    if (q0 == q1) return;
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
    const bool perspective = projection.perspective();
    for (std::size_t first = q0; first < q1;) {
        std::size_t end = first;
        while (end < q1 && quads[end].brick == quads[first].brick) ++end;
        GpTask task = begin_task(quads[first].brick, true);
        std::map<std::uint32_t, Batch> batches;
        std::uint64_t draws = 0, extra = 0;
        for (std::size_t q = first; q < end; ++q) {
            std::uint64_t here = 0;
            for_each_region(quads[q].x0, quads[q].y0, quads[q].x1, quads[q].y1, rc, rr, regions_x, [&](std::size_t r) {
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
        const std::uint32_t brick = quads[first].brick;
        const glm::ivec3 brick_lo =
            glm::ivec3(static_cast<int>(brick % static_cast<std::uint32_t>(bricks_.x)),
                       static_cast<int>((brick / static_cast<std::uint32_t>(bricks_.x)) %
                                        static_cast<std::uint32_t>(bricks_.y)),
                       static_cast<int>(brick / static_cast<std::uint32_t>(bricks_.x * bricks_.y))) *
            edge;
        const std::uint64_t plane_texels = static_cast<std::uint64_t>(std::min(edge + 1, n[b] - brick_lo[b])) *
                                           static_cast<std::uint64_t>(std::min(edge + 1, n[c] - brick_lo[c]));
        append_ops(work.ops, kWilsonTexel, plane_texels);
        append_ops(work.ops, perspective ? kWilsonQuadPerspective : kWilsonQuadParallel, end - first);
        append_ops(work.ops, kWilsonRegionShift, extra);
        append_ops(work.ops, kWilsonSliceSetup, setups);
        append_ops(work.ops, kWilsonCoefficient, draws * kQuadCoefficients + setups * 9);
        append_ops(work.ops, kWilsonBin, draws);
        counts.quad_draws += draws;
        end_task(task, batches, program_.quad, &setup_sent, &setup_runs);
        first = end;
    }
    for (std::size_t r = 0; r < setup_runs.size(); ++r)
        if (setup_runs[r] > 0)
            work.regions[r].steps.push_back(RegionStep{kNoBatch, program_.composite, setup_runs[r], 0});
}

std::size_t FrameBuilder::record_slab(std::uint32_t l, std::size_t next_point) {
    GpPhase& work = frame.work;
    while (next_point < points.size() && points[next_point].layer == l) {
        std::size_t end = next_point;
        while (end < points.size() && points[end].layer == l && points[end].brick == points[next_point].brick) ++end;
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
                const glm::ivec2 origin = region_origin(r);
                const int x0 = std::max(sq.x0, origin.x), y0 = std::max(sq.y0, origin.y),
                          x1 = std::min(sq.x1, origin.x + rc - 1), y1 = std::min(sq.y1, origin.y + rr - 1);
                sheet_pixels += static_cast<std::uint64_t>(x1 - x0 + 1) * static_cast<std::uint64_t>(y1 - y0 + 1);
                auto [it, fresh] = blocks.try_emplace(r, std::array<int, 4>{x0, y0, x1, y1});
                if (!fresh)
                    it->second = {std::min(it->second[0], x0), std::min(it->second[1], y0), std::max(it->second[2], x1),
                                  std::max(it->second[3], y1)};
            });
        }
        for (const auto& [r, box] : blocks) {
            const std::uint64_t pixels =
                static_cast<std::uint64_t>(box[2] - box[0] + 1) * static_cast<std::uint64_t>(box[3] - box[1] + 1);
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
            end_task(task, batches, program_.point, nullptr, nullptr);
        }
        next_point = end;
    }
    return next_point;
}

void FrameBuilder::record_readout() {
    GpPhase& work = frame.work;
    for (std::size_t region = 0; region < region_count; ++region) {
        const glm::ivec2 origin = region_origin(region);
        const int w = std::min(rc, width - origin.x);
        const int h = std::min(rr, height - origin.y);
        RegionWork& rw = work.regions[renderer_of_region(region)];
        rw.steps.push_back(RegionStep{kNoBatch, program_.readout, 1, 0});
        rw.readout_pixels += static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    }
    append_ops(work.regions_on_one_processor, kWilsonQuadPixel, counts.quad_pixels);
    append_ops(work.regions_on_one_processor, kWilsonCompositePixel, counts.composited_pixels);
    append_ops(work.regions_on_one_processor, kWilsonPointPixel, counts.point_pixels);
}

}  // namespace pp5::slicing
