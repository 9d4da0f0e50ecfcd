#pragma once
// Levoy's volume rendering workstation on the simulated machine, one frame at a time:
//   1. the renderers' PPs classify and shade the voxels that need it (pp_shading.h);
//   2. when the classification changed the set of non-empty voxels, the renderers send every GP the
//      voxels' emptiness and each GP rebuilds the pyramid of binary volumes (binary_pyramid.h);
//   3. the GPs cast rays pass after pass of adaptive refinement (ray_caster.h, adaptive_refinement.h),
//      fetching voxels over the ring into their caches.
// The frame is computed first and recorded as the machine's work (sim/timing/recorded_work.h); the
// timing engine then times it on the machine (sim/timing/frame_engine.h), or one processor does it all
// (sim/timing/one_processor.h).
// Each change between frames reruns only what it needs (Levoy's animation sequences): a light or
// colour change reshades, a classification change reclassifies and rebuilds the pyramid only if the
// non-empty set moved, an observer move reshades only if the shading depends on the view. GP caches
// survive between frames and are dropped when the PPs' voxels change; while the observer and the
// non-empty set stay, rays start at the depth buffer's first non-empty sample.

#include "kernels/levoy/binary_pyramid.h"
#include "kernels/levoy/levoy_costs.h"
#include "kernels/levoy/levoy_settings.h"
#include "kernels/levoy/voxel_blocks.h"
#include "scene/render/camera.h"
#include "scene/render/image.h"
#include "scene/render/polygon.h"
#include "scene/render/region_of_interest.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

#include <optional>
#include <vector>

namespace pp5 {

struct LevoyFrameInputs {
    Camera camera;
    Classification classification;
    ColorMap colors;
    PhongLighting lighting;
    bool classification_changed = true;
    bool lighting_changed = true;            // lights or colours
    std::optional<RegionOfInterest> region;  // the volume-of-interest tool, when in use
};

// The rays' counts, which no timing parameter changes.
struct RayCastCounts {
    std::uint64_t rays = 0;
    std::uint64_t samples = 0;
    std::uint64_t samples_skipped = 0;
    std::uint64_t pyramid_steps = 0;
    std::uint64_t rays_terminated = 0;
    std::uint64_t pixels_filled = 0;
};

// What the ray casting of one frame did: the rays' own counts (from the functional layer) and the
// machine's (from the timing engine), summed over the GPs.
struct RayCastReport : RayCastCounts {
    Tick start = 0;
    Tick end = 0;
    std::vector<Tick> pass_end;  // when each refinement pass's last tile reached the frame buffer
    std::uint64_t cache_hits = 0;
    std::uint64_t cache_misses = 0;
    std::uint64_t fetch_requests = 0;    // to renderers, a block of voxels each
    std::uint64_t blocks_refreshed = 0;  // asked for again, in refresh messages, after the PPs reshaded
    std::uint64_t context_switches = 0;
    Tick gp_busy = 0;
    Tick gp_wait = 0;
    Tick renderer_busy = 0;
    Tick ring_busy = 0;
    std::uint64_t events = 0;
};

// What a frame asks of the machine, recorded by the functional layer, with what Levoy's metrics need
// besides. None of it depends on a timing parameter (costs, clocks, GP count, ring, caches), so the same
// work can be timed again on machines that differ only in those: calibration fits and GP-count sweeps
// do that instead of re-rendering. Phases are named: classification, region_of_interest, shading,
// scan_conversion, pyramid, ray_casting (each only when the frame needs it).
struct LevoyFrameWork {
    FrameWork machine;
    std::uint64_t polygons = 0;  // including degenerate ones, which need no pass
    RayCastCounts rays;
};

// The polygons scan-converted into the volume after each reshading (Levoy's Figure 5).
struct GeometryReport {
    bool ran = false;
    std::uint64_t polygons = 0;
    std::uint64_t slots = 0;  // slot runs over all renderers
    Tick start_ps = 0;
    Tick end_ps = 0;
    double polygons_per_second() const {
        return end_ps > start_ps ? static_cast<double>(polygons) / ticks_to_seconds(end_ps - start_ps) : 0.0;
    }
};

struct RefinementPassReport {
    Tick end_ps = 0;  // from the frame's start to the pass's last pixels at the frame buffer
    std::uint64_t rays = 0;
    std::uint64_t samples = 0;
    std::uint64_t pixels_cast = 0;  // so far, in all passes
    Image image;                    // the picture after this pass
};

// When a frame's work happened on one machine, in Levoy's terms.
struct LevoyFrameTiming {
    Tick start_ps = 0;
    Tick end_ps = 0;
    PpFrameReport pixel_processors;
    PpProgramPass region;  // the volume-of-interest pass, when it ran
    GeometryReport geometry;
    Tick pyramid_ps = 0;  // distributing the emptiness bits and building
    RayCastReport ray_cast;
    Tick crude_ps() const {
        return ray_cast.pass_end.empty() ? end_ps - start_ps : ray_cast.pass_end.front() - start_ps;
    }
    Tick refined_ps() const { return end_ps - start_ps; }
    Tick duration_ps() const { return end_ps - start_ps; }
};

// Levoy's view of a frame's timing on any machine (the engine's, or one processor's).
LevoyFrameTiming levoy_frame_timing(const LevoyFrameWork& work, const FrameTiming& timing);
// Times `work` on `machine` from its current time; GP caches carry over from earlier frames.
LevoyFrameTiming time_levoy_frame(Machine& machine, const LevoyFrameWork& work);

// A frame: what it computed and recorded, and (once timed) when its work happened.
struct LevoyFrameReport : LevoyFrameTiming {
    bool pyramid_rebuilt = false;
    std::uint64_t pyramid_cells_occupied = 0;
    bool caches_invalidated = false;  // the GPs' cached voxels were stale at the frame's start
    bool caches_refreshed = false;    // ... and the GPs asked again for the blocks they had used (levoy.after_reshade)
    bool depth_buffer_used = false;
    std::vector<RefinementPassReport> passes;
    Image final_image;    // the last pass's picture
    LevoyFrameWork work;  // what the frame asked of the machine, to time again elsewhere
    Tick duration_ps() const { return end_ps - start_ps; }
};

struct LevoyImageSettings {
    int width = 512;
    int height = 512;
    float sample_step = 1.0f;
    float termination_opacity = 0.95f;  // >= 1: no early termination
    glm::vec3 background{0.0f};
};

class LevoyRenderer {
public:
    // Places the volume in the PPs (InputError if it does not fit).
    LevoyRenderer(Machine& machine, const Volume& volume, const LevoySettings& settings,
                  const LevoyImageSettings& image);

    // Polygons to scan-convert into the volume (voxel coordinates), from the next frame on. With
    // polygons, any change that reruns a PP pass reruns classification and shading too, so that the
    // polygons are matted into fresh voxels exactly once.
    void set_polygons(const std::vector<PolygonSpec>& polygons);

    // Computes the frame and records its work (report.work), untimed.
    LevoyFrameReport record(const LevoyFrameInputs& frame);
    // record(), then times the work on this renderer's machine.
    LevoyFrameReport render(const LevoyFrameInputs& frame);

    // InputError naming the machine key when a volume of `dims` cannot be placed on the PPs or its
    // pyramid does not fit in the GPs' memory beside their caches: the constructor's own refusals,
    // askable before the volume is read.
    static void check_fits(const Machine& machine, glm::ivec3 dims, const LevoySettings& settings);

    const PpShading& pixel_processors() const { return pixel_processors_; }
    // The codes the GPs cast through, as the PPs last left them.
    const ShadedCodes& shaded_codes() const { return shaded_; }
    // The same, decoded to floats (for the reference compositor and tests).
    ShadedVolume shaded_volume() const { return shaded_.decoded(); }
    const BinaryPyramid& pyramid() const { return pyramid_; }
    const VoxelBlocks& blocks() const { return blocks_; }

private:
    // What a frame changes: the view its colours are shaded for, and which PP passes it needs.
    struct FrameChanges {
        ShadingView view;
        bool classify = false, reshade = false, capping = false, region_moved = false;
    };
    FrameChanges what_changes(const LevoyFrameInputs& frame);
    void rebuild_pyramid(const ShadedCodes* unscaled, const std::optional<PpPassWork>& emptiness,
                         std::size_t emptiness_at, LevoyFrameReport& report);
    // A PP pass over every voxel, and what one processor would do for it instead.
    Phase voxel_pass(const char* name, const PpPassWork& pass, LevoyOp per_voxel,
                     std::uint64_t per_voxel_count = 1) const;
    // The classification and shading passes the frame's changes call for, into `work`.
    void record_shading(const LevoyFrameInputs& frame, const FrameChanges& changes, FrameWork& work);
    Phase scan_convert();
    struct CappedShading {
        std::optional<PpPassWork> stationary_lights;
        PpPassWork shading;
    };
    CappedShading capped_shading(const LevoyFrameInputs& frame, const ShadingView& view, bool region_moved);
    Phase pyramid_phase() const;
    Phase cast_frame(const Camera& camera, LevoyFrameReport& report);

    Machine& machine_;
    LevoySettings settings_;
    LevoyImageSettings image_;
    glm::ivec3 dims_;
    glm::vec3 spacing_;
    PpShading pixel_processors_;
    VoxelBlocks blocks_;
    std::shared_ptr<const BlockDirectory> directory_;
    ShadedCodes shaded_;
    BinaryPyramid pyramid_;
    std::vector<PreparedPolygon> polygons_;
    std::vector<double> polygon_areas_;  // each one's area within the volume
    bool polygons_changed_ = false;
    std::optional<ShadingView> shaded_for_;
    std::optional<RegionOfInterest> region_;
    std::optional<Camera> depth_for_;
    std::vector<std::uint32_t> depth_;
    bool first_frame_ = true;
};

// Fills a recorded frame's report with when its work happened.
void apply_timing(LevoyFrameReport& report, const LevoyFrameTiming& timing);

}  // namespace pp5
