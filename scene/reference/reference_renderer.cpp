#include "scene/reference/reference_renderer.h"

#include "scene/reference/composite_loop.h"
#include "scene/reference/post_classified.h"
#include "scene/reference/voxel_opacity.h"

#include <chrono>
#include <utility>

namespace pp5 {

namespace {

class Stopwatch {
public:
    double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point start_ = Clock::now();
};

}  // namespace

CompositeSettings RenderSettings::composite_settings() const {
    CompositeSettings s;
    s.width = width;
    s.height = height;
    s.sample_step = sample_step;
    s.early_termination = early_termination;
    s.termination_opacity = termination_opacity;
    s.background = background;
    s.skip_empty_space = skip_empty_space;
    return s;
}

ReferenceRenderer::ReferenceRenderer(Volume volume) : volume_(std::move(volume)) {}

ReferenceRenderer::~ReferenceRenderer() = default;

void ReferenceRenderer::set_classification(Classification classification, ColorMap color_map) {
    validate_classification(classification);
    validate_color_map(color_map);
    if (classification != classification_) {
        classification_ = std::move(classification);
        post_occupancy_.reset();
        invalidate_opacities();
    }
    if (color_map != color_map_) {
        color_map_ = std::move(color_map);
        shaded_view_.reset();
    }
}

void ReferenceRenderer::set_region(std::optional<RegionOfInterest> region) {
    if (region == region_) return;
    region_ = std::move(region);
    invalidate_opacities();
}

void ReferenceRenderer::set_polygons(const std::vector<PolygonSpec>& polygons) {
    if (polygons.empty()) mattes_.reset();
    else mattes_.emplace(volume_.dims(), polygons);
    invalidate_opacities();
}

void ReferenceRenderer::invalidate_opacities() {
    opacities_.reset();
    occupancy_.reset();
    on_demand_.reset();
    shaded_view_.reset();
}

void ReferenceRenderer::set_lighting(PhongLighting lighting) {
    validate_lighting(lighting);
    if (lighting != lighting_) {
        lighting_ = lighting;
        shaded_view_.reset();
    }
}

const GradientField& ReferenceRenderer::gradients() {
    RenderStats ignored;
    ensure_gradients(ignored);
    return *gradients_;
}

std::span<const float> ReferenceRenderer::opacities() {
    RenderStats ignored;
    ensure_opacities(ignored);
    return *opacities_;
}

void ReferenceRenderer::ensure_gradients(RenderStats& stats) {
    if (gradients_) return;
    const Stopwatch watch;
    gradients_ = compute_gradients(volume_);
    bricks_.emplace(volume_, *gradients_);
    stats.gradients_computed = true;
    stats.seconds.gradients = watch.seconds();
}

void ReferenceRenderer::ensure_opacities(RenderStats& stats) {
    ensure_gradients(stats);
    if (opacities_) return;
    const Stopwatch watch;
    opacities_ = classify_voxels(volume_, *gradients_, classification_);
    if (region_) scale_by_region(*opacities_, volume_.dims(), *region_);
    if (region_ && region_->cap) {
        // A region moved frame after frame caps again in the arrays of the last frame.
        if (!capped_gradients_) capped_gradients_.emplace();
        cap_gradients(volume_, *gradients_, *region_, *capped_gradients_);
        if (capped_bricks_) capped_bricks_->refill(volume_, *capped_gradients_);
        else capped_bricks_.emplace(volume_, *capped_gradients_);
    } else {
        capped_gradients_.reset();
        capped_bricks_.reset();
    }
    if (mattes_) {
        // Voxels only a polygon fills are not empty space.
        std::vector<float> non_empty = *opacities_;
        mattes_->mark_non_empty(non_empty);
        occupancy_ = occupancy_from_opacity(volume_.dims(), non_empty);
    } else {
        occupancy_ = occupancy_from_opacity(volume_.dims(), *opacities_);
    }
    brick_opacities_ = bricks_->gather(*opacities_);
    // Fresh zeros: outside occupied blocks nothing is ever shaded, and zero opacity is right there.
    on_demand_.reset();
    shaded_.dims = volume_.dims();
    shaded_.spacing = volume_.spacing();
    shaded_.rgba.assign(volume_.voxel_count(), glm::vec4(0.0f));  // in the last classification's storage
    on_demand_ = std::make_unique<OnDemandShading>(shaded_, *occupancy_);
    shaded_view_.reset();
    stats.opacities_computed = true;
    stats.seconds.opacities = watch.seconds();
}

void ReferenceRenderer::ensure_post_classified_occupancy(RenderStats& stats) {
    ensure_gradients(stats);
    if (post_occupancy_) return;
    const Stopwatch watch;
    if (!value_ranges_) value_ranges_ = compute_block_value_ranges(volume_, *gradients_);
    post_occupancy_ = occupancy_from_value_ranges(*value_ranges_, classification_);
    stats.opacities_computed = true;
    stats.seconds.opacities = watch.seconds();
}

void ReferenceRenderer::ensure_colour_view(const ShadingView& view, bool hold_colours, RenderStats& stats) {
    if (shaded_view_ && (hold_colours || *shaded_view_ == view)) return;
    on_demand_->invalidate();
    shaded_view_ = view;
    stats.colours_computed = true;
}

Image ReferenceRenderer::render(const Camera& camera, const RenderSettings& settings, RenderStats* stats) {
    const CompositeSettings composite_settings = settings.composite_settings();
    validate_camera(camera);
    validate_composite_settings(composite_settings);
    const Stopwatch total;
    RenderStats local;
    Image image;
    if (settings.resampling == ResamplingOrder::ShadeThenInterpolate) {
        ensure_opacities(local);
        ensure_colour_view(make_shading_view(camera, volume_.dims(), volume_.spacing()),
                           settings.hold_colours_when_camera_moves, local);
        // Blocks shaded later in a held-colour animation must match the earlier ones: the held view.
        const BlockShader shader(volume_, capped_gradients_ ? *capped_gradients_ : *gradients_, *opacities_,
                                 *occupancy_, color_map_, lighting_, *shaded_view_,
                                 capped_bricks_ ? &*capped_bricks_ : &*bricks_, brick_opacities_,
                                 mattes_ ? &*mattes_ : nullptr);
        const Stopwatch watch;
        image = detail::composite_loop(shaded_, *occupancy_, camera, composite_settings, &local.composite,
                                       [&](glm::ivec3 corner) { on_demand_->ensure_cell(corner, shader); });
        local.seconds.compositing = watch.seconds();
        local.voxels_shaded = on_demand_->take_voxels_shaded();
        local.seconds.shading = on_demand_->take_shading_seconds();
        local.blocks = occupancy_->block_count();
        local.blocks_occupied = occupancy_->occupied_count();
    } else {
        ensure_post_classified_occupancy(local);
        const Stopwatch watch;
        image = render_post_classified(volume_, *gradients_, classification_, color_map_, lighting_, camera,
                                       composite_settings, *post_occupancy_, &local.composite);
        local.seconds.compositing = watch.seconds();
        local.blocks = post_occupancy_->block_count();
        local.blocks_occupied = post_occupancy_->occupied_count();
    }
    local.seconds.total = total.seconds();
    if (stats != nullptr) *stats = local;
    return image;
}

}  // namespace pp5
