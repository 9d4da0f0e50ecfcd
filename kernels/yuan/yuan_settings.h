#pragma once
// The parameters of Yuan, Nguyen, Xu and Chen's hybrid point/splat splatting ("yuan.*"): which voxels
// are splats and which points, the reconstruction kernel and its footprint table, the depth bands,
// the point filter, and how the work is spread over the machine. Each says where its value comes from:
// the paper (Yuan et al. 2003) or ours where the paper is silent.

#include "sim/core/config.h"
#include "sim/core/param.h"
#include "sim/timing/recorded_work.h"

#include <string>

namespace pp5 {

// Which primitive a voxel becomes: by its projected size (the paper), or all one kind (to compare).
enum class PrimitiveMode { Hybrid, AllSplats, AllPoints };
// Where the footprint table is indexed: the paper's affine index i corrected by the cone angle, or the
// exact distance from the kernel's centre to the pixel's ray.
enum class FootprintIndex { Yuan, Exact };
// How splats meet the picture: one at a time ("over", the paper) or summed into the band's sheet.
enum class SplatCompositing { Over, Sheet };
// Who filters the points: the GPs, sending each band's summed sheet as a pixel block, or the renderers,
// drawing every point as a quadratic of its own.
enum class PointPath { GpSheets, Renderer };

struct YuanSettings {
    PrimitiveMode primitives = PrimitiveMode::Hybrid;
    double switch_pixels = 1.0;                         // a voxel is a splat when its projected spacing exceeds this
    double kernel_radius = 2.0;                         // voxels
    double kernel_sigma = 0.7;                          // voxels
    int footprint_table_bits = 6;                       // entries of the footprint table: 2^bits over i^2
    double footprint_alpha_step_degrees = 15.0 / 32.0;  // rows of the corrected table, one per step of cone angle
    FootprintIndex footprint_index = FootprintIndex::Yuan;
    SplatCompositing splat_compositing = SplatCompositing::Over;
    double band_voxels = 1.0;          // depth of a band, in voxel spacings
    double point_filter_radius = 0.0;  // pixels; 0: matched to the splat footprint at the switch
    PointPath point_path = PointPath::GpSheets;
    int brick_voxels = 32;  // edge of the bricks dealt to GPs
    TaskAssignment brick_assignment = TaskAssignment::Static;
    int accumulator_bits = 12;  // fraction bits of the renderers' colour and opacity accumulators

    // The point filter's radius in pixels after the automatic choice.
    double point_radius_pixels() const;

    static const ParamGroup& params();
    // Reads and checks the settings: a bad combination is an InputError naming the key.
    static YuanSettings from(const MachineConfig& config);
};

}  // namespace pp5
