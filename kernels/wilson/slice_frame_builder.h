#pragma once
// One frame of Wilson et al.'s hybrid slicing, built step by step (HybridSlicer::render): the layers,
// the quads and points (slice_frame_builder.cpp), every region drawn as its renderer draws it
// (slice_region_drawing.cpp), and the machine's work recorded (slice_work.cpp). Each step reads what
// the steps before it left.

#include "kernels/shared/screen_regions/screen_projection.h"
#include "kernels/wilson/hybrid_slicer.h"
#include "kernels/wilson/slice_geometry.h"

#include <array>
#include <cstdint>
#include <map>
#include <vector>

namespace pp5::slicing {

enum class LayerKind { Plane, Slab };
struct Layer {
    LayerKind kind = LayerKind::Plane;
    int index = 0;  // the plane, or the slab's lower plane (-1 below the first)
};

// A texel cell drawn this frame.
struct Quad {
    std::uint32_t layer = 0;
    std::uint32_t brick = 0;
    std::int32_t i = 0, j = 0;
    std::array<Quadratic, 4> channel;  // red, green, blue, opacity in [0, 1], of the screen position
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

// A stored point as this frame draws it.
struct DrawnPoint {
    std::uint32_t layer = 0;
    std::uint32_t brick = 0;
    std::uint32_t index = 0;  // storage order
    bool drawn = false;
    bool offscreen = false;
    int side = 0;
    PointSquare square;  // screen pixels
};

inline std::size_t linear(glm::ivec3 d, glm::ivec3 p) {
    return static_cast<std::size_t>(p.x) +
           static_cast<std::size_t>(d.x) *
               (static_cast<std::size_t>(p.y) + static_cast<std::size_t>(d.y) * static_cast<std::size_t>(p.z));
}

// Over a region, what a layer asks: which regions each primitive reaches, row-major region indices.
template <class Visit>
void for_each_region(int x0, int y0, int x1, int y1, int rc, int rr, int regions_x, Visit&& visit) {
    for (int ry = y0 / rr; ry <= y1 / rr; ++ry)
        for (int rx = x0 / rc; rx <= x1 / rc; ++rx)
            visit(static_cast<std::size_t>(ry) * static_cast<std::size_t>(regions_x) + static_cast<std::size_t>(rx));
}

// One frame's construction, its steps run in order by build().
class FrameBuilder {
public:
    FrameBuilder(const HybridSlicer& slicer, const WilsonSettings& settings, const RegionMachine& machine,
                 const HybridVolume& hybrid, glm::vec3 spacing, glm::ivec3 bricks, const SliceFormat& format,
                 const SlicePrograms& programs, const ShadedCodes& shaded_texels, const PointLook& point_look,
                 const Camera& view, int image_width, int image_height, glm::vec3 image_background)
        : slicer_(slicer),
          settings_(settings),
          machine_(machine),
          hybrid_(&hybrid),
          spacing_(spacing),
          bricks_(bricks),
          format_(format),
          programs_(programs),
          texels(shaded_texels),
          look(point_look),
          camera(view),
          width(image_width),
          height(image_height),
          background(image_background),
          projection(view, image_width, image_height),
          low(hybrid.low_resolution()),
          n(low.dims()),
          k(hybrid.factor()),
          stack(choose_slices(view_direction(hybrid, spacing, view, projection))),
          a(stack.axis),
          b((a + 1) % 3),
          c((a + 2) % 3),
          min_spacing(std::min({spacing.x, spacing.y, spacing.z})),
          one(format.one()),
          edge(settings.brick_voxels),
          rc(machine.region_columns),
          rr(machine.region_rows),
          regions_x((image_width + rc - 1) / rc),
          regions_y((image_height + rr - 1) / rr),
          region_count(static_cast<std::size_t>(regions_x) * static_cast<std::size_t>(regions_y)),
          gp_sheets(settings.point_path == WilsonPointPath::GpSheets) {
        counts.slice_axis = a;
    }

    HybridFrame build() {
        make_layers();
        make_quads();
        make_points();
        order_quads();
        bin_by_region();
        draw_regions();
        record_work();
        return std::move(frame);
    }

private:
    // What drawing a region added to the frame's counts.
    struct RegionTally {
        std::uint64_t quad_pixels = 0, composites = 0, composited_pixels = 0, point_pixels = 0, blocks = 0,
                      block_pixels = 0;
    };
    // A GP task's message to one renderer.
    struct Batch;
    // Where the region programs the work runs sit in the phase's list.
    struct ProgramIndex {
        std::uint32_t setup = 0, quad = 0, composite = 0, point = 0, readout = 0;
    };

private:
    // Eye to the volume's centre under perspective, else the camera's forward.
    static glm::vec3 view_direction(const HybridVolume& hybrid, glm::vec3 spacing, const Camera& camera,
                                    const ScreenProjection& projection) {
        const glm::vec3 center = glm::vec3(hybrid.error_grid() / hybrid.error_grid_factor() - 1) * spacing * 0.5f;
        return projection.perspective() ? center - camera.eye : camera.forward();
    }

    // The distance a ray travels between two slices, in the voxels opacity is measured per.
    double path_voxels(glm::dvec3 world, double thickness) const {
        const glm::dvec3 d = projection.perspective() ? world - glm::dvec3(camera.eye) : glm::dvec3(camera.forward());
        const double cosine = std::abs(d[a]) / glm::length(d);
        return thickness * spacing_[a] / (std::max(cosine, 1e-6) * min_spacing);
    }

    std::uint32_t brick_at(glm::ivec3 texel) const {
        const glm::ivec3 bc = texel / edge;
        return static_cast<std::uint32_t>(bc.x + bricks_.x * (bc.y + bricks_.y * bc.z));
    }
    std::uint32_t brick_of(const HybridPoint& point) const { return slicer_.brick_of(point); }

    // The layers, back to front.
    void make_layers();
    // Each plane's quads, brick by brick (planes in parallel).
    void make_quads();
    // The points: shaded, corrected and sized (in parallel), then in (layer, brick, storage) order.
    void make_points();
    // The hybrid volume's point m, as points[m]: its layer and brick, the opacity it adds over the
    // low-resolution volume, its square on screen and its premultiplied colour.
    void place_point(std::size_t m, double grid_spacing, double point_world);
    // All quads in layer order.
    void order_quads();
    // Regions and their lists (in layer order, as the primitives are).
    void bin_by_region();

    // Every region drawn as its renderer draws it, with and without the points.
    void draw_regions();
    // One region, into `out`, with or without the points.
    RegionTally draw_region(std::size_t r, bool with_points, Image& out) const;
    // Layer l's quads in region r's list from `next`, over the slice's setup, then the slice's composite;
    // returns the list's next entry.
    std::size_t draw_slice(SliceRegion& region, std::uint32_t l, const std::vector<std::uint32_t>& list,
                           std::size_t next, glm::ivec2 origin, RegionTally& tally) const;
    // A slab's points in the region, entries [first, end) of its list.
    // `block` is scratch for the GPs' point blocks, kept by the caller across slabs.
    void draw_slab_points(SliceRegion& region, const std::vector<std::uint32_t>& list, std::size_t first,
                          std::size_t end, glm::ivec2 origin, RegionTally& tally,
                          std::vector<std::array<std::int32_t, 4>>& block) const;
    // The region's pixels over the background.
    void write_pixels(const SliceRegion& region, glm::ivec2 origin, Image& out) const;

    // The machine's work: per layer, one GP task per brick with something in it.
    void record_work();
    std::shared_ptr<const BlockDirectory> texel_blocks() const;
    // A slice's tasks (one per brick of its quads) and its composites.
    void record_slice(std::uint32_t l);
    // A slab's tasks, one per brick of its points from `next_point`; returns the first point after them.
    std::size_t record_slab(std::uint32_t l, std::size_t next_point);
    void record_readout();
    GpTask begin_task(std::uint32_t brick, bool fetch);
    // Packs and sends the task's batches, the first batch to each renderer also carrying the slice's
    // setup when `setup_sent` is given.
    void end_task(GpTask& task, const std::map<std::uint32_t, Batch>& batches, std::uint32_t program,
                  std::vector<bool>* setup_sent, const std::vector<std::uint32_t>* setup_runs);
    std::uint32_t renderer_of_region(std::size_t region) const {
        return static_cast<std::uint32_t>(region % static_cast<std::size_t>(machine_.renderers));
    }
    glm::ivec2 region_origin(std::size_t r) const {
        return {static_cast<int>(r % static_cast<std::size_t>(regions_x)) * rc,
                static_cast<int>(r / static_cast<std::size_t>(regions_x)) * rr};
    }

    const HybridSlicer& slicer_;
    const WilsonSettings& settings_;
    const RegionMachine& machine_;
    const HybridVolume* hybrid_;
    glm::vec3 spacing_;
    glm::ivec3 bricks_;
    const SliceFormat& format_;
    const SlicePrograms& programs_;
    const ShadedCodes& texels;
    const PointLook& look;
    const Camera& camera;
    int width, height;
    glm::vec3 background;
    ScreenProjection projection;
    const Volume& low;
    glm::ivec3 n;
    int k;
    SliceStack stack;
    int a, b, c;
    double min_spacing;
    std::int64_t one;
    int edge;
    int rc, rr, regions_x, regions_y;
    std::size_t region_count;
    bool gp_sheets;
    HybridFrame frame;
    HybridCounts& counts = frame.counts;
    std::vector<Layer> layers;
    std::vector<std::uint32_t> plane_layer, slab_layer;  // each plane's and slab's place in `layers`
    std::vector<SlicePlane> planes;
    std::vector<std::vector<Quad>> plane_quads;
    std::vector<HybridCounts> plane_counts;
    std::vector<DrawnPoint> points;
    std::vector<Quad> quads;
    std::vector<std::size_t> first_quad_of_layer;
    std::vector<std::vector<std::uint32_t>> region_quads, region_points;
    ProgramIndex program_;
};

}  // namespace pp5::slicing
