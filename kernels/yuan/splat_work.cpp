#include "kernels/yuan/splat_stages.h"

#include "kernels/yuan/yuan_costs.h"

#include <algorithm>
#include <memory>

namespace pp5::splatting {

namespace {

constexpr std::uint32_t kUnitBits = 48;         // a voxel as the renderers stream it: RGBA and its place in the brick
constexpr std::uint32_t kCachedVoxelBits = 64;  // and as a GP keeps it
constexpr std::uint64_t kHeaderBits = 64;       // a batch's header: kind, band, brick, count
constexpr std::uint64_t kCoefficientBits = 32;
constexpr std::uint64_t kConstantBits = 16;

// The bricks' voxels as the GPs fetch them: per brick, the part each renderer streams.
std::shared_ptr<const BlockDirectory> brick_directory(const std::vector<std::vector<std::uint32_t>>& brick_parts) {
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
    return std::make_shared<const BlockDirectory>(std::uint64_t{largest} * kCachedVoxelBits, kUnitBits,
                                                  std::move(first_part), std::move(parts));
}

// Walks the items in the renderers' order, chunk by chunk, with each region's list beside it for the
// pixels its primitives changed.
class WorkRecorder {
public:
    WorkRecorder(const FrameSetup& f, const RegionPrograms& programs, const std::map<int, const PpTable*>& rows,
                 const std::vector<Item>& items, const std::vector<ScreenPrimitive>& primitives, RegionLists& lists,
                 const std::vector<RegionDrawn>& drawn, SplatFrame& frame)
        : f_(f),
          items_(items),
          primitives_(primitives),
          lists_(lists),
          drawn_(drawn),
          work_(frame.work),
          counts_(frame.counts),
          gp_sheets_(f.settings.point_path == PointPath::GpSheets),
          cursor_(f.regions.count(), 0),
          next_composite_(f.regions.count(), 0) {
        // Region programs: the splat program of each footprint row used, then the others.
        for (const auto& [row, table] : rows) {
            splat_program_.emplace(row, static_cast<std::uint32_t>(work_.region_programs.size()));
            work_.region_programs.push_back(programs.splat(*table));
        }
        counts_.footprint_rows = splat_program_.size();
        point_program_ = add_program(gp_sheets_ ? programs.sheet_add() : programs.point());
        composite_program_ = add_program(programs.band_composite());
        readout_program_ = add_program(programs.readout());
        work_.regions.resize(static_cast<std::size_t>(f.machine.renderers));
    }

    void record() {
        for (std::size_t first = 0; first < items_.size();) {
            std::size_t end = first;
            while (end < items_.size() && items_[end].band == items_[first].band &&
                   items_[end].brick == items_[first].brick)
                ++end;
            record_chunk(first, end);
            if (end == items_.size() || items_[end].band != items_[first].band) end_band(items_[first].band);
            first = end;
        }
        counts_.splat_pixels = splat_pixels_;
        counts_.point_pixels = point_pixels_;
        read_out();
    }

private:
    // Per renderer a chunk touches: its batch's bits and its steps.
    struct Batch {
        std::uint64_t bits = kHeaderBits;
        std::map<std::uint32_t, std::uint32_t> runs;  // program -> runs
        std::uint64_t write_words = 0;
    };
    // What the GP did for a chunk, in operations it is charged for.
    struct ChunkOps {
        std::uint64_t splats = 0, points = 0, extra_regions = 0, coefficients = 0, bins = 0, sheet_pixels = 0;
    };
    using Box = std::pair<glm::ivec2, glm::ivec2>;

    std::uint32_t add_program(PpProgram program) {
        work_.region_programs.push_back(std::move(program));
        return static_cast<std::uint32_t>(work_.region_programs.size() - 1);
    }
    Batch& batch_of(std::map<std::uint32_t, Batch>& batches, std::size_t region) const {
        return batches[static_cast<std::uint32_t>(f_.renderer_of_region(region))];
    }

    // One primitive binned to one region: its batch's bits and runs, and the GP's operations.
    void bin(const ScreenPrimitive& p, bool splat, std::size_t region, std::map<std::uint32_t, Batch>& batches,
             std::map<std::size_t, Box>& point_blocks, ChunkOps& ops) {
        // splat: quadratics, constants and the table row; point: four paraboloids of four coefficients
        const std::uint64_t splat_bits = (f_.exact ? 2 : 1) * 6 * kCoefficientBits + 4 * kConstantBits + kConstantBits;
        const std::uint64_t point_bits = 4 * 4 * kCoefficientBits;
        const RegionEntry& entry = lists_[region][cursor_[region]++];
        ++ops.bins;
        if (splat) {
            Batch& batch = batch_of(batches, region);
            splat_pixels_ += entry.pixels;
            ++batch.runs[splat_program_.at(p.row)];
            batch.bits += splat_bits;
            ops.coefficients += (f_.exact ? 12 : 6) + 4;
            ++counts_.splat_regions;
            return;
        }
        ++counts_.point_regions;
        if (gp_sheets_) {
            batch_of(batches, region);  // the renderer gets a batch even before its block is added
            ops.sheet_pixels += entry.pixels;
            auto [it, fresh] = point_blocks.try_emplace(region, glm::ivec2(p.x0, p.y0), glm::ivec2(p.x1, p.y1));
            if (!fresh) {
                it->second.first = glm::min(it->second.first, glm::ivec2(p.x0, p.y0));
                it->second.second = glm::max(it->second.second, glm::ivec2(p.x1, p.y1));
            }
            return;
        }
        Batch& batch = batch_of(batches, region);
        point_pixels_ += entry.pixels;
        ++batch.runs[point_program_];
        batch.bits += point_bits;
        ops.coefficients += 16;
    }

    // The GPs' sheet blocks of a chunk: each covers the chunk's points' box within its region, two words
    // (four 16-bit values) a pixel.
    void add_point_blocks(const std::map<std::size_t, Box>& point_blocks, std::map<std::uint32_t, Batch>& batches) {
        for (const auto& [region, box] : point_blocks) {
            const glm::ivec2 origin = f_.regions.origin(region);
            const glm::ivec2 lo = glm::max(box.first, origin);
            const glm::ivec2 hi =
                glm::min(box.second, origin + glm::ivec2(f_.regions.columns - 1, f_.regions.rows - 1));
            const std::uint64_t pixels =
                static_cast<std::uint64_t>(hi.x - lo.x + 1) * static_cast<std::uint64_t>(hi.y - lo.y + 1);
            Batch& batch = batch_of(batches, region);
            ++batch.runs[point_program_];
            batch.write_words += 2 * pixels;
            batch.bits += 64 * pixels + 64;
        }
    }

    void record_chunk(std::size_t first, std::size_t end) {
        ++counts_.chunks;
        std::map<std::uint32_t, Batch> batches;
        std::map<std::size_t, Box> point_blocks;  // region -> box, for the GPs' sheets
        ChunkOps ops;
        for (std::size_t k = first; k < end; ++k) {
            if (items_[k].kind == Kind::Culled || !primitives_[k].visible()) continue;
            const ScreenPrimitive& p = primitives_[k];
            const bool splat = items_[k].kind == Kind::Splat;
            (splat ? ops.splats : ops.points) += 1;
            std::uint64_t regions_here = 0;
            f_.regions.for_each_under(p, [&](std::size_t region) {
                ++regions_here;
                bin(p, splat, region, batches, point_blocks, ops);
            });
            ops.extra_regions += regions_here - 1;
        }
        add_point_blocks(point_blocks, batches);
        record_task(items_[first].brick, end - first, ops, batches);
    }

    // The task: fetch the brick (a cache hit after its first chunk on this GP), then the chunk's work.
    void record_task(std::uint32_t brick, std::size_t voxels, const ChunkOps& ops,
                     const std::map<std::uint32_t, Batch>& batches) {
        GpTask task;
        task.key = brick;
        task.first_item = static_cast<std::uint32_t>(work_.items.size());
        task.item_count = 1;
        work_.items.push_back(GpItem{static_cast<std::uint32_t>(work_.steps.size()), 1});
        work_.steps.push_back(GpStep{0, 0, brick});
        task.first_finish_op = static_cast<std::uint32_t>(work_.ops.size());
        std::uint64_t words = 0;
        for (const auto& [renderer, batch] : batches) words += (batch.bits + 31) / 32;
        append_ops(work_.ops, kYuanVoxel, voxels);
        append_ops(work_.ops, kYuanSplatSetup, ops.splats);
        append_ops(work_.ops, kYuanRegionShift, ops.extra_regions);
        append_ops(work_.ops, kYuanCoefficient, ops.coefficients);
        if (gp_sheets_) append_ops(work_.ops, kYuanSheetPixel, ops.sheet_pixels);
        else append_ops(work_.ops, kYuanPointSetup, ops.points);
        append_ops(work_.ops, kYuanBin, ops.bins);
        append_ops(work_.ops, kYuanPackWord, words);
        task.finish_op_count = static_cast<std::uint32_t>(work_.ops.size()) - task.first_finish_op;
        task.first_batch = static_cast<std::uint32_t>(work_.batches.size());
        for (const auto& [renderer, batch] : batches) {
            const auto index = static_cast<std::uint32_t>(work_.batches.size());
            work_.batches.push_back(PrimitiveBatch{renderer, batch.bits});
            // A batch exists only for a renderer something was binned to, so it always has a step.
            for (const auto& [program, runs] : batch.runs)
                work_.regions[renderer].steps.push_back(
                    RegionStep{index, program, runs, program == point_program_ && gp_sheets_ ? batch.write_words : 0});
            ++counts_.batches;
            counts_.batch_words += (batch.bits + 31) / 32;
        }
        task.batch_count = static_cast<std::uint32_t>(batches.size());
        work_.tasks.push_back(task);
    }

    // At a band's end each renderer composites the sheets of its regions that hold something.
    void end_band(std::uint32_t band) {
        std::vector<std::uint32_t> composites(static_cast<std::size_t>(f_.machine.renderers), 0);
        for (std::size_t region = 0; region < drawn_.size(); ++region) {
            std::size_t& next = next_composite_[region];
            if (next < drawn_[region].bands.size() && drawn_[region].bands[next] == band) {
                ++next;
                ++composites[f_.renderer_of_region(region)];
            }
        }
        for (std::size_t renderer = 0; renderer < composites.size(); ++renderer)
            if (composites[renderer] > 0)
                work_.regions[renderer].steps.push_back(
                    RegionStep{kNoBatch, composite_program_, composites[renderer], 0});
        ++counts_.bands;
    }

    void read_out() {
        for (std::size_t region = 0; region < f_.regions.count(); ++region) {
            const glm::ivec2 origin = f_.regions.origin(region);
            const int w = std::min(f_.regions.columns, f_.width - origin.x);
            const int hgt = std::min(f_.regions.rows, f_.height - origin.y);
            RegionWork& rw = work_.regions[f_.renderer_of_region(region)];
            rw.steps.push_back(RegionStep{kNoBatch, readout_program_, 1, 0});
            rw.readout_pixels += static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(hgt);
        }
        // What a lone processor does instead of the renderers: every pixel each primitive changed.
        append_ops(work_.regions_on_one_processor, kYuanSplatPixel, counts_.splat_pixels);
        if (!gp_sheets_) append_ops(work_.regions_on_one_processor, kYuanPointPixel, counts_.point_pixels);
        append_ops(work_.regions_on_one_processor, kYuanCompositePixel, counts_.composited_pixels);
    }

    const FrameSetup& f_;
    const std::vector<Item>& items_;
    const std::vector<ScreenPrimitive>& primitives_;
    RegionLists& lists_;
    const std::vector<RegionDrawn>& drawn_;
    GpPhase& work_;
    SplatCounts& counts_;
    bool gp_sheets_;
    std::map<int, std::uint32_t> splat_program_;
    std::uint32_t point_program_ = 0, composite_program_ = 0, readout_program_ = 0;
    std::vector<std::size_t> cursor_;          // per region: the next entry of its list, walked in item order
    std::vector<std::size_t> next_composite_;  // per region: its next composited band
    std::uint64_t splat_pixels_ = 0, point_pixels_ = 0;
};

}  // namespace

void record_work(const FrameSetup& f, const RegionPrograms& programs, const std::map<int, const PpTable*>& rows,
                 const std::vector<Item>& items, const std::vector<ScreenPrimitive>& primitives, RegionLists& lists,
                 const std::vector<RegionDrawn>& drawn, const std::vector<std::vector<std::uint32_t>>& brick_parts,
                 SplatFrame& frame) {
    frame.work.groups = 1;
    frame.work.assignment = f.settings.brick_assignment;
    frame.work.blocks = brick_directory(brick_parts);
    WorkRecorder(f, programs, rows, items, primitives, lists, drawn, frame).record();
}

}  // namespace pp5::splatting
