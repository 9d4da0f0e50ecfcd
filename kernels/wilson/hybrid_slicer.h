#pragma once
// One frame of Wilson et al.'s hybrid rendering as Pixel-planes 5 would compute it, and the work it
// asks of the machine.
//
// The low-resolution volume's slices along the axis most parallel to the view are drawn back to front,
// and the points between two slices (a slab) are drawn after the farther slice and before the nearer
// one. The GPs own bricks of the low-resolution volume and the points inside them. For each slice,
// each GP with a brick on it fetches the brick's shaded texels from the renderers (kept in its cache
// from slice to slice), corrects their opacity for the slice spacing, turns every cell with an opaque
// corner into a quad (four quadratics, one per channel, and its cell key), bins the quads by 128x128
// screen region and sends each renderer one batch; then, for the slab, it shades and sizes its points
// and sends them the same way (or composites them itself and sends the pixels). A renderer sets a
// slice up (which cell each pixel sees), draws its quads into the slice buffer, composites the slice
// under what it holds, then draws the slab's points over it; at the end it reads its region out.
//
// The picture comes from the renderers' fixed-point arithmetic (slice_programs.h), evaluated region by
// region on the host's threads, so it depends on neither the GP count nor any timing parameter. The
// frame also renders the low-resolution volume alone (no points), the paper's comparison.

#include "kernels/shared/pp_volume/shaded_codes.h"
#include "kernels/shared/screen_regions/region_machine.h"
#include "kernels/wilson/hybrid_volume.h"
#include "kernels/wilson/slice_programs.h"
#include "kernels/wilson/wilson_settings.h"
#include "scene/reference/shading_view.h"
#include "scene/render/camera.h"
#include "scene/render/classification.h"
#include "scene/render/image.h"
#include "scene/render/shading.h"
#include "sim/timing/recorded_work.h"

#include <cstdint>
#include <functional>
#include <map>
#include <vector>

namespace pp5 {

struct HybridCounts {
    int slice_axis = 2;
    std::uint64_t slices = 0;            // planes with at least one quad
    std::uint64_t cells = 0;             // texel cells examined
    std::uint64_t quads = 0;             // cells with an opaque corner, drawn
    std::uint64_t cells_behind_eye = 0;  // cells reaching the eye's plane (not drawn)
    std::uint64_t quads_offscreen = 0;
    std::uint64_t quad_draws = 0;        // quads summed over the regions they reach
    std::uint64_t quad_pixels = 0;       // pixels a quad wrote
    std::uint64_t slice_composites = 0;  // (slice, region) composites
    std::uint64_t composited_pixels = 0;
    std::uint64_t points = 0;              // stored
    std::uint64_t points_drawn = 0;        // with some opacity after the correction, on screen
    std::uint64_t points_transparent = 0;  // the correction left nothing to add (the volume is too opaque there)
    std::uint64_t points_offscreen = 0;
    std::uint64_t point_draws = 0;  // points summed over the regions they reach
    std::uint64_t point_pixels = 0;
    std::uint64_t point_blocks = 0;  // gp_sheets: (slab, brick, region) blocks sent
    std::uint64_t block_pixels = 0;
    std::map<int, std::uint64_t> point_sizes;  // square side in pixels -> points
    std::uint64_t tasks = 0;
    std::uint64_t batches = 0;
    std::uint64_t batch_words = 0;
};

struct HybridFrame {
    Image image;
    Image low_resolution;  // the slices alone
    HybridCounts counts;
    GpPhase work;  // the "slicing" phase
};

// How points are coloured this frame (the GPs shade them; the PPs shade the texels).
struct PointLook {
    const Classification* classification = nullptr;
    const ColorMap* colors = nullptr;
    PhongLighting lighting;
    ShadingView view;
};

class HybridSlicer {
public:
    // `spacing`: the original voxel size; `hybrid` must outlive the slicer.
    HybridSlicer(const WilsonSettings& settings, const RegionMachine& machine, const HybridVolume& hybrid,
                 glm::vec3 spacing);
    // `texels`: the low-resolution volume's shaded voxels (colour not premultiplied, opacity per voxel).
    HybridFrame render(const ShadedCodes& texels, const PointLook& look, const Camera& camera, int width, int height,
                       glm::vec3 background) const;
    const SlicePrograms& programs() const { return programs_; }
    glm::ivec3 bricks() const { return bricks_; }
    // The brick a point belongs to (that of the low-resolution sample nearest it): its GP keeps it.
    std::uint32_t brick_of(const HybridPoint& point) const;
    // What each brick's points take in its GP's memory.
    std::vector<std::uint64_t> resident_bits_by_brick() const;

private:
    WilsonSettings settings_;
    RegionMachine machine_;
    const HybridVolume* hybrid_;
    glm::vec3 spacing_;
    glm::ivec3 bricks_;
    SliceFormat format_;
    SlicePrograms programs_;
};

}  // namespace pp5
