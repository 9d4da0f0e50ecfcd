#pragma once
// One frame of Yuan et al.'s hybrid splatting as Pixel-planes 5 would compute it, and the work it asks
// of the machine.
//
// The voxels that classification left non-transparent are taken brick by brick (the GPs' unit) and
// into depth bands; each becomes a splat when its projected spacing passes the switch, else a point.
// Every (band, brick) chunk is one GP task: fetch the brick's colours from the renderers (kept in the
// GP's cache from frame to frame), transform and split its voxels, set up the splats' conics and the
// points, bin them by 128x128 screen region and send each renderer one batch. A renderer takes its
// batches in (band, brick) order, drawing splats front to back and summing points into the band's
// sheet, which it composites at the band's end; then it reads its regions out to the frame buffer.
//
// The picture comes from the renderers' fixed-point arithmetic (region_programs.h), evaluated region by
// region in the same order on the host's threads; it depends on neither the GP count nor the brick
// assignment nor any timing parameter, and the recorded work can be re-timed on any machine.

#include "kernels/shared/pp_volume/shaded_codes.h"
#include "kernels/shared/screen_regions/region_machine.h"
#include "kernels/yuan/footprint.h"
#include "kernels/yuan/region_programs.h"
#include "kernels/yuan/yuan_settings.h"
#include "scene/render/camera.h"
#include "scene/render/image.h"
#include "sim/timing/recorded_work.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace pp5 {

namespace splatting {
struct FrameBuffers;
}

// What a frame did, counted as it was done.
struct SplatCounts {
    std::uint64_t voxels = 0;  // non-transparent voxels taken by the GPs
    std::uint64_t splats = 0;
    std::uint64_t points = 0;
    std::uint64_t culled = 0;     // kernels reaching the eye's plane
    std::uint64_t offscreen = 0;  // splats and points wholly outside the picture
    std::uint64_t bands = 0;      // depth bands holding voxels
    std::uint64_t chunks = 0;     // (band, brick) GP tasks
    std::uint64_t batches = 0;    // messages to renderers
    std::uint64_t batch_words = 0;
    std::uint64_t splat_regions = 0;  // splat draws summed over regions (>= splats drawn)
    std::uint64_t point_regions = 0;
    std::uint64_t splat_pixels = 0;  // pixels a splat changed, summed
    std::uint64_t point_pixels = 0;
    std::uint64_t band_composites = 0;  // (band, region) sheet composites
    std::uint64_t composited_pixels = 0;
    std::uint64_t footprint_rows = 0;                  // distinct footprint tables (PP programs) drawn with
    std::vector<std::uint64_t> primitives_per_region;  // row-major over the screen's regions
    double splat_fraction() const {
        const auto drawn = splats + points;
        return drawn == 0 ? 0.0 : static_cast<double>(splats) / static_cast<double>(drawn);
    }
};

struct SplatFrame {
    Image image;
    Image primitive_map;  // red where splats drew, grey where points did (Yuan et al.'s Figure 8a)
    SplatCounts counts;
    GpPhase work;  // the "splatting" phase
};

class HybridSplatter {
public:
    HybridSplatter(const YuanSettings& settings, const RegionMachine& machine, glm::ivec3 dims, glm::vec3 spacing);
    ~HybridSplatter();
    // Splats the shaded voxels (colours not premultiplied; opacity per voxel step) for one camera. One
    // frame at a time: the per-voxel arrays are kept for the next frame.
    SplatFrame render(const ShadedCodes& voxels, const Camera& camera, int width, int height, glm::vec3 background);

    const RegionPrograms& programs() const { return programs_; }
    // The footprint rows: corrected for the cone angle (perspective, Yuan's index), or plain.
    const FootprintTables& tables(bool corrected) const { return corrected ? corrected_ : plain_; }

private:
    YuanSettings settings_;
    RegionMachine machine_;
    glm::ivec3 dims_;
    glm::vec3 spacing_;
    glm::ivec3 bricks_;
    RegionFormat format_;
    RegionPrograms programs_;
    GaussianFootprint kernel_;
    FootprintTables corrected_;
    FootprintTables plain_;
    std::unique_ptr<splatting::FrameBuffers> buffers_;
};

}  // namespace pp5
