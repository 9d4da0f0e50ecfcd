#include "kernels/yuan/yuan_settings.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <cmath>

namespace pp5 {

namespace {
constexpr const char* kPaper = "Yuan, Nguyen, Xu, Chen 2003";
}

double YuanSettings::point_radius_pixels() const {
    // At the switch a splat's footprint has second moment 2 sigma^2 s^2 per axis pair; a paraboloid of
    // radius R has R^2 / 3. Equal moments make the picture continuous where the split falls.
    return point_filter_radius > 0 ? point_filter_radius : std::sqrt(6.0) * kernel_sigma * switch_pixels;
}

const ParamGroup& YuanSettings::params() {
    static const ParamGroup group = [] {
        ParamGroup g("yuan",
                     "Yuan et al.'s hybrid splatting: minified voxels as points filtered on screen, magnified ones as "
                     "perspective elliptical splats, drawn by the renderers over their screen regions");
        g.text("primitives", "hybrid", {"hybrid", "splats", "points"},
               "Which voxels are splats: those whose projected spacing passes the switch (hybrid), or every voxel one "
               "kind",
               Provenance::Paper,
               std::string(kPaper) + " sections 2 and 5 (the all-splat and all-point columns of Figure 9)")
            .real("switch_pixels", 1.0, "pixels", 0.01, 100,
                  "A voxel is a splat when its projected spacing (pixels per voxel) exceeds this, else a point",
                  Provenance::Paper,
                  std::string(kPaper) + " section 1: aliasing when splats project to less than one pixel")
            .real("kernel_radius", 2.0, "voxels", 0.5, 8,
                  "Radius where the spherical Gaussian reconstruction kernel is cut off", Provenance::Default,
                  "pp5sim: the paper gives none; 2 voxels as in Botha's shell splatting")
            .real("kernel_sigma", 0.7, "voxels", 0.1, 4, "Standard deviation of the Gaussian reconstruction kernel",
                  Provenance::Default,
                  "pp5sim: the paper says 'usually a Gaussian'; 0.7 voxels as in Botha's shell splatting")
            .integer("footprint_table_bits", 6, "bits", 2, 12,
                     "The footprint table has 2^bits entries over the squared index", Provenance::Default,
                     "pp5sim: the paper's table size is not given")
            .real("footprint_alpha_step_degrees", 15.0 / 32.0, "degrees", 0.01, 15,
                  "Cone-angle step between the rows of the corrected footprint table (one PP table per row)",
                  Provenance::Paper,
                  std::string(kPaper) + " section 4.2: a 2-D table over i and alpha, alpha below 15 degrees")
            .text(
                "footprint_index", "yuan", {"yuan", "exact"},
                "How a pixel indexes the footprint: the affine index corrected for the cone angle (yuan), or the exact "
                "distance from the kernel's centre to the pixel's ray (two quadratics and a divide per pixel)",
                Provenance::Paper,
                std::string(kPaper) + " section 4.2; its closed form corrected (d = sin(atan(i tan a)) / sin a)")
            .text("splat_compositing", "over", {"over", "sheet"},
                  "Composite each splat on its own (over), or sum the band's splats into its sheet like points",
                  Provenance::Paper, std::string(kPaper) + " section 4.1: 'we always perform over for splats'")
            .real("band_voxels", 1.0, "voxels", 0.05, 64,
                  "Depth of the bands within which points are summed before compositing", Provenance::Paper,
                  std::string(kPaper) + " section 4.1: 'within a certain depth range (e.g., 1 unit)'")
            .real("point_filter_radius", 0.0, "pixels", 0, 16,
                  "Radius of the paraboloid filter placed at each pixel for points; 0 matches the splat footprint at "
                  "the switch "
                  "(sqrt(6) sigma switch_pixels)",
                  Provenance::Default,
                  "pp5sim: the paper says 'a circular filter'; the paraboloid is what the QEE evaluates")
            .text(
                "point_path", "gp_sheets", {"gp_sheets", "renderer"},
                "Who filters the points: the GPs, sending each band's summed sheet as a pixel block, or the renderers, "
                "drawing each point as its own quadratic",
                Provenance::Default,
                "pp5sim: measured by bench_yuan (the renderer path is slower when points crowd into few regions)")
            .integer("brick_voxels", 32, "voxels", 4, 256, "Edge of the bricks of voxels dealt to the GPs",
                     Provenance::Default, "pp5sim")
            .text("brick_assignment", "static", {"static", "work_queue"},
                  "Which GP transforms which brick: dealt round-robin, or handed out by the host as GPs ask",
                  Provenance::Default, "pp5sim")
            .integer("accumulator_bits", 12, "bits", 8, 16,
                     "Fraction bits of the renderers' colour and opacity accumulators (the band sheets have two more)",
                     Provenance::Default, "pp5sim: 8 bits would band under hundreds of faint splats");
        return g;
    }();
    return group;
}

YuanSettings YuanSettings::from(const MachineConfig& config) {
    YuanSettings s;
    const std::string mode = config.text("yuan.primitives");
    s.primitives = mode == "splats"   ? PrimitiveMode::AllSplats
                   : mode == "points" ? PrimitiveMode::AllPoints
                                      : PrimitiveMode::Hybrid;
    s.switch_pixels = config.real("yuan.switch_pixels");
    s.kernel_radius = config.real("yuan.kernel_radius");
    s.kernel_sigma = config.real("yuan.kernel_sigma");
    s.footprint_table_bits = static_cast<int>(config.integer("yuan.footprint_table_bits"));
    s.footprint_alpha_step_degrees = config.real("yuan.footprint_alpha_step_degrees");
    s.footprint_index = config.text("yuan.footprint_index") == "exact" ? FootprintIndex::Exact : FootprintIndex::Yuan;
    s.splat_compositing =
        config.text("yuan.splat_compositing") == "sheet" ? SplatCompositing::Sheet : SplatCompositing::Over;
    s.band_voxels = config.real("yuan.band_voxels");
    s.point_filter_radius = config.real("yuan.point_filter_radius");
    s.point_path = config.text("yuan.point_path") == "renderer" ? PointPath::Renderer : PointPath::GpSheets;
    s.brick_voxels = static_cast<int>(config.integer("yuan.brick_voxels"));
    s.brick_assignment =
        config.text("yuan.brick_assignment") == "work_queue" ? TaskAssignment::WorkQueue : TaskAssignment::Static;
    s.accumulator_bits = static_cast<int>(config.integer("yuan.accumulator_bits"));
    // The ranges above are the parameter table's; what they cannot say is checked here.
    if (s.kernel_sigma * 1.5 > s.kernel_radius)
        reject_field(
            "yuan.kernel_sigma",
            fmt::format("a Gaussian of sigma {} cut off at radius {} keeps too little of itself (the radius must be at "
                        "least 1.5 sigma)",
                        s.kernel_sigma, s.kernel_radius));
    if (s.point_radius_pixels() < 0.5)
        reject_field("yuan.point_filter_radius",
                     fmt::format("a point filter of radius {:.3f} pixels can fall between pixel centres (at least 0.5)",
                                 s.point_radius_pixels()));
    return s;
}

}  // namespace pp5
