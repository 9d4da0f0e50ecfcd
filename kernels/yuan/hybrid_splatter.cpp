#include "kernels/yuan/hybrid_splatter.h"

#include "kernels/yuan/splat_stages.h"

#include <glm/trigonometric.hpp>

#include <algorithm>
#include <map>
#include <vector>

namespace pp5 {

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
      plain_(kernel_, settings.footprint_table_bits, settings.accumulator_bits, 1.0, false),
      buffers_(std::make_unique<splatting::FrameBuffers>()) {}

HybridSplatter::~HybridSplatter() = default;

SplatFrame HybridSplatter::render(const ShadedCodes& voxels, const Camera& camera, int width, int height,
                                  glm::vec3 background) {
    using namespace splatting;
    const ScreenProjection projection(camera, width, height);
    const double h = std::min({spacing_.x, spacing_.y, spacing_.z});
    const bool exact = settings_.footprint_index == FootprintIndex::Exact && projection.perspective();
    const bool corrected = !exact && projection.perspective();
    const int rc = machine_.region_columns, rr = machine_.region_rows;
    const FrameSetup f{settings_,
                       machine_,
                       dims_,
                       spacing_,
                       bricks_,
                       format_,
                       projection,
                       width,
                       height,
                       h,
                       settings_.kernel_radius * h,
                       exact,
                       tables(corrected),
                       ScreenRegions{rc, rr, (width + rc - 1) / rc, (height + rr - 1) / rr}};
    SplatFrame frame;
    SplatCounts& counts = frame.counts;

    std::vector<std::vector<std::uint32_t>> brick_parts;
    take_voxels(f, voxels, brick_parts, *buffers_);
    std::vector<Item>& items = buffers_->items;
    counts.voxels = items.size();
    order_by_band(f, items);
    make_primitives(f, voxels, items, buffers_->primitives);
    const std::vector<ScreenPrimitive>& primitives = buffers_->primitives;
    RegionLists lists = bin_by_region(f, items, primitives, counts);
    const std::map<int, const PpTable*> rows = footprint_rows(f, items, primitives);

    const std::vector<RegionDrawn> drawn =
        draw_regions(f, programs_.blend(), items, primitives, rows, lists, background, frame);
    for (std::size_t r = 0; r < f.regions.count(); ++r) {
        counts.primitives_per_region.push_back(lists[r].size());
        counts.band_composites += drawn[r].bands.size();
        counts.composited_pixels += drawn[r].composited_pixels;
    }
    record_work(f, programs_, rows, items, primitives, lists, drawn, brick_parts, frame);
    return frame;
}

}  // namespace pp5
