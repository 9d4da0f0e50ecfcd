#include "kernels/wilson/wilson_settings.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <string>

namespace pp5 {

namespace {
constexpr const char* kPaper = "Wilson, Ma, McCormick 2002";
std::string paper(const char* where) { return std::string(kPaper) + " " + where; }
}  // namespace

const ParamGroup& WilsonSettings::params() {
    static const ParamGroup group = [] {
        ParamGroup g("wilson",
                     "Wilson et al.'s hybrid rendering: a low-resolution volume drawn as axis-aligned slices by the "
                     "renderers, with points wherever its reconstruction misses the original");
        g.integer(
             "downsample_factor", 2, "voxels", 1, 8,
             "k: each low-resolution voxel stands for k^3 voxels of the original (1 renders the original as slices)",
             Provenance::Paper, paper("section 5: 512^3 data shown at 256^3 and 128^3 (k = 2 and 4)"))
            .text(
                "downsample", "cubic", {"cubic", "box", "min"},
                "How a low-resolution sample is made: Catmull-Rom tricubic interpolation at its position, the mean of "
                "its "
                "k^3 voxels, or the least voxel under its trilinear hat (the reconstruction then never overestimates)",
                Provenance::Paper,
                paper("section 3 ('most images ... cubic interpolation') and 3.2 (the minimum function)"))
            .real("overestimate_limit", -1, "value units", -1, 1e9,
                  "With cubic or box, a low-resolution sample is at most this far above the minimum under its hat "
                  "(negative: no limit)",
                  Provenance::Paper,
                  paper("section 3.2: 'the minimum amount the low-resolution representation can overestimate'"))
            .integer(
                "error_grid_factor", 1, "per voxel", 1, 4,
                "Error samples per original voxel along each axis (above 1 the original is interpolated tricubically)",
                Provenance::Paper,
                paper("section 3.1: usually the original resolution; 1024^3 for the 512x512x2048 Furby"))
            .real("error_threshold", 1.0 / 64.0, "of the value range", 0, 1,
                  "A point is inserted where the reconstruction's error exceeds this share of the value range",
                  Provenance::Paper, paper("sections 3.1 and 5: 1/64, 1/32, 1/16, 1/12 and 1/8"))
            .text("error_sign", "magnitude", {"magnitude", "positive"},
                  "Which errors earn a point: either sign, or only where the low-resolution volume is too low (a point "
                  "can "
                  "only add opacity)",
                  Provenance::Paper, paper("sections 3.1 (the error value) and 3.2 (points only add)"))
            .integer("max_points", 0, "points", 0, 1'000'000'000,
                     "Keep only this many points, those of largest error (0: every point past the threshold)",
                     Provenance::Paper,
                     paper("section 3.1: 'a given number of points ... with the highest error magnitude'"))
            .real("point_overlap", 1.1, "ratio", 1, 4,
                  "A point's side over the error grid's projected spacing, so neighbours overlap slightly",
                  Provenance::Default, "pp5sim: the paper says 'overlap slightly' without a figure")
            .real("point_opacity_scale", 1.0, "ratio", 0, 4,
                  "Scales every point's opacity (the paper's manual transparency)", Provenance::Paper,
                  paper("section 4.1: 'global point transparency can be manually adjusted'"))
            .text("point_path", "gp_sheets", {"gp_sheets", "renderer"},
                  "Who composites a slab's points: the renderers, each point a square primitive, or the GPs, sending "
                  "each "
                  "(slab, brick)'s composited pixels as a block",
                  Provenance::Default,
                  "pp5sim: measured on wilson-mr-head, 1.85M points: 0.88 s as GP blocks against 2.55 s as "
                  "renderer primitives (each a full program run over 16K PPs)")
            .text("opacity_correction", "per_slice", {"per_slice", "none"},
                  "Correct each slice's opacity for the distance a ray travels between slices (k voxels over the "
                  "cosine of "
                  "the view's angle to the slice normal), or use the voxels' opacity as it is (the paper's hardware)",
                  Provenance::Default, "pp5sim: the paper's paletted textures do not correct")
            .integer("brick_voxels", 16, "voxels", 2, 256,
                     "Edge of the bricks of the low-resolution volume (and their points) that each GP owns",
                     Provenance::Default, "pp5sim")
            .integer("accumulator_bits", 12, "bits", 8, 16, "Fraction bits of the renderers' colour and opacity fields",
                     Provenance::Default, "pp5sim: as the yuan kernel's");
        return g;
    }();
    return group;
}

WilsonSettings WilsonSettings::from(const MachineConfig& config) {
    WilsonSettings s;
    s.downsample_factor = static_cast<int>(config.integer("wilson.downsample_factor"));
    const std::string filter = config.text("wilson.downsample");
    s.downsample = filter == "box" ? Downsample::Box : filter == "min" ? Downsample::Minimum : Downsample::Cubic;
    const double limit = config.real("wilson.overestimate_limit");
    s.overestimate_limit = limit < 0 ? std::numeric_limits<double>::infinity() : limit;
    s.error_grid_factor = static_cast<int>(config.integer("wilson.error_grid_factor"));
    s.error_threshold = config.real("wilson.error_threshold");
    s.error_sign = config.text("wilson.error_sign") == "positive" ? ErrorSign::Positive : ErrorSign::Magnitude;
    s.max_points = static_cast<std::uint64_t>(config.integer("wilson.max_points"));
    s.point_overlap = config.real("wilson.point_overlap");
    s.point_opacity_scale = config.real("wilson.point_opacity_scale");
    s.point_path =
        config.text("wilson.point_path") == "gp_sheets" ? WilsonPointPath::GpSheets : WilsonPointPath::Renderer;
    s.opacity_correction = config.text("wilson.opacity_correction") == "none" ? SliceOpacityCorrection::None
                                                                              : SliceOpacityCorrection::PerSlice;
    s.brick_voxels = static_cast<int>(config.integer("wilson.brick_voxels"));
    s.accumulator_bits = static_cast<int>(config.integer("wilson.accumulator_bits"));
    if (s.downsample == Downsample::Minimum && std::isfinite(s.overestimate_limit))
        reject_field("wilson.overestimate_limit",
                     "limits how far cubic or box samples exceed the minimum; with downsample = \"min\" there is "
                     "nothing to limit");
    return s;
}

}  // namespace pp5
