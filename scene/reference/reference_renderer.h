#pragma once
// The host floating-point renderer with Levoy's stage caching ("Optimization for animation
// sequences"): each stage's result is kept and recomputed only when its inputs change.
//   gradients             - per volume (never recomputed)
//   opacities, occupancy  - per classification
//   voxel colours         - per colour map, lighting and shading view (direction to viewer, depth
//                           frame); a camera move reshades, a zoom or a new image size does not
//   image                 - every render
// So an animation that moves only the camera costs shading plus compositing per frame. Voxels are
// shaded on demand, block by block, when a ray first needs them (on_demand_shading.h): the image is
// bit-identical to composite(shade_voxels(...)), but blocks hidden behind opaque surfaces are never
// shaded. Optionally
// (hold_colours_when_camera_moves) the colours are kept while the camera moves: Levoy's "simple
// optimization", with highlights and depth cues frozen at the first view.
//
// InterpolateThenShade classifies and shades at the samples (post_classified.h); it shares the
// gradients and keeps its own occupancy, built from per-block value ranges.
//
// Not thread-safe: one render at a time (each render uses all cores).

#include "scene/reference/composite.h"
#include "scene/reference/gradient_field.h"
#include "scene/reference/occupancy_grid.h"
#include "scene/reference/on_demand_shading.h"
#include "scene/reference/polygon_matte.h"
#include "scene/reference/shaded_volume.h"
#include "scene/reference/shading_view.h"
#include "scene/render/camera.h"
#include "scene/render/classification.h"
#include "scene/render/image.h"
#include "scene/render/region_of_interest.h"
#include "scene/render/resampling_order.h"
#include "scene/render/shading.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace pp5 {

struct RenderSettings {
    int width = 512;
    int height = 512;
    float sample_step = 1.0f;           // voxels (of the smallest spacing) between samples
    float termination_opacity = 0.95f;  // early ray termination (Levoy's 1 - epsilon); at 1 no pixel
                                        // changes: rays stop only once fully opaque
    glm::vec3 background{0.0f};
    ResamplingOrder resampling = ResamplingOrder::ShadeThenInterpolate;
    bool early_termination = true;                // false: rays always run to the far side
    bool skip_empty_space = true;                 // never changes a pixel; off only to measure its effect
    bool hold_colours_when_camera_moves = false;  // ShadeThenInterpolate: Levoy's approximation

    CompositeSettings composite_settings() const;
};

// Host seconds per stage in the last render (0 when the stage was reused). Wall-clock time: never
// compare it in tests or write it where output must be reproducible.
struct StageSeconds {
    double gradients = 0.0;
    double opacities = 0.0;    // classification and occupancy
    double compositing = 0.0;  // includes on-demand shading
    double shading = 0.0;      // of which shading, summed over threads (thread-seconds, not wall)
    double total = 0.0;
};

struct RenderStats {
    CompositeStats composite;
    bool gradients_computed = false;
    bool opacities_computed = false;    // classification (and its occupancy grid)
    bool colours_computed = false;      // voxel colours invalidated and (re)shaded on demand
                                        // (ShadeThenInterpolate only)
    std::uint64_t voxels_shaded = 0;    // in this render
    std::uint64_t blocks = 0;           // occupancy blocks of the volume
    std::uint64_t blocks_occupied = 0;  // of them, occupied under this classification
    StageSeconds seconds;
};

class ReferenceRenderer {
public:
    explicit ReferenceRenderer(Volume volume);
    ~ReferenceRenderer();
    // The caches refer to each other: not copyable or movable.
    ReferenceRenderer(const ReferenceRenderer&) = delete;
    ReferenceRenderer& operator=(const ReferenceRenderer&) = delete;

    const Volume& volume() const { return volume_; }

    // Throw pp5::InputError for an invalid classification, colour map or lighting.
    void set_classification(Classification classification, ColorMap color_map);
    void set_lighting(PhongLighting lighting);
    // Levoy's volume-of-interest tool, scaling voxel opacities after classification (none: no region).
    // The region and the polygons below act on voxels, so they are rendered when shading before
    // interpolating (the voxels' order); renders_region() says whether `settings` does.
    void set_region(std::optional<RegionOfInterest> region);
    // Polygons scan-converted into the volume and matted over its shaded voxels (polygon_matte.h).
    void set_polygons(const std::vector<PolygonSpec>& polygons);
    static bool renders_region(const RenderSettings& settings) {
        return settings.resampling == ResamplingOrder::ShadeThenInterpolate;
    }

    const Classification& classification() const { return classification_; }
    const ColorMap& color_map() const { return color_map_; }
    const PhongLighting& lighting() const { return lighting_; }

    // Throws pp5::InputError for an invalid camera or settings.
    Image render(const Camera& camera, const RenderSettings& settings, RenderStats* stats = nullptr);

    // The cached stages, computed on first use: for kernels that start from the same data.
    const GradientField& gradients();
    std::span<const float> opacities();

private:
    // The voxels' opacities (classification, region, polygons) must be made again, and with them the
    // occupancy and every shaded block.
    void invalidate_opacities();
    void ensure_gradients(RenderStats& stats);
    void ensure_opacities(RenderStats& stats);
    void ensure_post_classified_occupancy(RenderStats& stats);
    void ensure_colour_view(const ShadingView& view, bool hold_colours, RenderStats& stats);

    Volume volume_;
    Classification classification_;
    ColorMap color_map_;
    PhongLighting lighting_;
    std::optional<RegionOfInterest> region_;
    std::optional<PolygonMattes> mattes_;

    std::optional<GradientField> gradients_;
    std::optional<VoxelBricks> bricks_;  // gradients and values block by block, for shading
    // With a capping region: the gradients shading uses (capped in the region's transition zone), and
    // their bricks; classification keeps the volume's own.
    std::optional<GradientField> capped_gradients_;
    std::optional<VoxelBricks> capped_bricks_;
    std::optional<BlockValueRanges> value_ranges_;
    // Valid while their inputs are unchanged; cleared by the setters.
    std::optional<std::vector<float>> opacities_;
    std::optional<OccupancyGrid> occupancy_;       // from opacities_
    std::vector<float> brick_opacities_;           // opacities_ in brick order, for shading
    std::optional<OccupancyGrid> post_occupancy_;  // from value ranges and classification_
    ShadedVolume shaded_;                          // storage kept across frames; zero outside occupied blocks
    std::unique_ptr<OnDemandShading> on_demand_;   // block states for shaded_, per opacities_
    std::optional<ShadingView> shaded_view_;       // the view the ready blocks were shaded for
};

}  // namespace pp5
