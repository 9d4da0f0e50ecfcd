#pragma once
// Levoy's volume rendering workstation on the simulated machine, one frame at a time:
//   1. the renderers' PPs classify and shade the voxels that need it (pp_shading.h);
//   2. when the classification changed the set of non-empty voxels, the renderers send every GP the
//      voxels' emptiness and each GP rebuilds the pyramid of binary volumes (binary_pyramid.h);
//   3. the GPs cast rays pass after pass of adaptive refinement (ray_caster.h, adaptive_refinement.h),
//      fetching voxels over the ring into their caches (ray_cast_timing.h).
// Each change between frames reruns only what it needs (Levoy's animation sequences): a light or
// colour change reshades, a classification change reclassifies and rebuilds the pyramid only if the
// non-empty set moved, an observer move reshades only if the shading depends on the view. GP caches
// survive between frames and are dropped when the PPs' voxels change; while the observer and the
// non-empty set stay, rays start at the depth buffer's first non-empty sample.

#include "kernels/levoy/binary_pyramid.h"
#include "kernels/levoy/pp_shading.h"
#include "kernels/levoy/ray_cast_timing.h"
#include "kernels/levoy/voxel_blocks.h"
#include "kernels/render/camera.h"
#include "kernels/render/polygon.h"
#include "kernels/render/region_of_interest.h"
#include "kernels/render/image.h"

#include <optional>
#include <vector>

namespace pp5 {

struct LevoyFrameInputs {
    Camera camera;
    Classification classification;
    ColorMap colors;
    PhongLighting lighting;
    bool classification_changed = true;
    bool lighting_changed = true;  // lights or colours
    std::optional<RegionOfInterest> region;  // the volume-of-interest tool, when in use
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

// What a frame asks of the machine, recorded by the functional layer. None of it depends on a timing
// parameter (costs, clocks, GP count, ring, caches), so the same work can be timed again on machines
// that differ only in those: calibration fits and GP-count sweeps do that instead of re-rendering.
struct PolygonWork {
    PpPassWork pass;
    std::uint64_t command_bits = 0;  // the host's broadcast of the polygon's QEE coefficients
    double area = 0.0;               // voxels^2: what a sequential scan-converter's work grows with
    int edges = 0;
};
struct PyramidWork {
    std::vector<int> slots_per_renderer;  // each renderer broadcasts one message a slot
    std::uint64_t bits_per_slot = 0;      // one emptiness bit per PP
    std::uint64_t cells = 0;              // every GP builds every cell
};
struct LevoyFrameWork {
    std::uint64_t voxels = 0;  // in the volume
    int jitter_samples = 1;    // subvoxel translations per voxel in scan-conversion
    PpFrameWork pixel_processors;
    std::optional<PpPassWork> region;
    bool scan_converted = false;
    std::uint64_t polygons = 0;           // including degenerate ones, which need no pass
    std::vector<PolygonWork> polygon_passes;
    bool invalidate_caches = false;
    std::optional<PyramidWork> pyramid;  // when the non-empty set changed
    RayCastJob ray_cast;
    RayAssignment assignment = RayAssignment::StaticTiles;
};

// When a frame's work happened on one machine.
struct LevoyFrameTiming {
    Tick start_ps = 0;
    Tick end_ps = 0;
    PpFrameReport pixel_processors;
    PpProgramPass region;
    GeometryReport geometry;
    Tick pyramid_ps = 0;
    RayCastReport ray_cast;
    Tick crude_ps() const { return ray_cast.pass_end.empty() ? end_ps - start_ps : ray_cast.pass_end.front() - start_ps; }
    Tick refined_ps() const { return end_ps - start_ps; }
};

// Times `work` on `machine` from its current time, with `blocks` for the GPs' voxel requests: the PP
// passes, the polygons, the pyramid, then the ray casting. GP caches carry over from earlier frames.
LevoyFrameTiming time_levoy_frame(Machine& machine, VoxelBlocks& blocks, const LevoyFrameWork& work);

struct LevoyFrameReport {
    Tick start_ps = 0;
    Tick end_ps = 0;
    PpFrameReport pixel_processors;
    PpProgramPass region;  // the volume-of-interest pass, when it ran
    GeometryReport geometry;
    bool pyramid_rebuilt = false;
    Tick pyramid_ps = 0;  // distributing the emptiness bits and building
    std::uint64_t pyramid_cells_occupied = 0;
    bool caches_invalidated = false;
    bool depth_buffer_used = false;
    RayCastReport ray_cast;
    std::vector<RefinementPassReport> passes;
    Image final_image;  // the last pass's picture
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
    // Places the volume in the PPs (InputError if it does not fit) and sizes the GP caches.
    LevoyRenderer(Machine& machine, const Volume& volume, const LevoySettings& settings, const LevoyImageSettings& image);

    // Polygons to scan-convert into the volume (voxel coordinates), from the next frame on. With
    // polygons, any change that reruns a PP pass reruns classification and shading too, so that the
    // polygons are matted into fresh voxels exactly once.
    void set_polygons(const std::vector<PolygonSpec>& polygons);

    LevoyFrameReport render(const LevoyFrameInputs& frame);

    const PpShading& pixel_processors() const { return pixel_processors_; }
    const ShadedVolume& shaded_volume() const { return shaded_; }
    const BinaryPyramid& pyramid() const { return pyramid_; }
    const VoxelBlocks& blocks() const { return blocks_; }

private:
    std::vector<PolygonWork> scan_convert();
    PyramidWork pyramid_work() const;
    RayCastJob cast_frame(const Camera& camera, LevoyFrameReport& report);

    Machine& machine_;
    LevoySettings settings_;
    LevoyImageSettings image_;
    glm::ivec3 dims_;
    glm::vec3 spacing_;
    PpShading pixel_processors_;
    VoxelBlocks blocks_;
    ShadedVolume shaded_;
    BinaryPyramid pyramid_;
    std::vector<PreparedPolygon> polygons_;
    bool polygons_changed_ = false;
    std::optional<ShadingView> shaded_for_;
    std::optional<RegionOfInterest> region_;
    std::optional<Camera> depth_for_;
    std::vector<std::uint32_t> depth_;
    bool first_frame_ = true;
};

// Whether voxel colours depend on where the observer is: a headlight, a highlight or depth cueing.
bool shading_depends_on_view(const PhongLighting& lighting);

}  // namespace pp5
