#pragma once
// The parameters of Wilson, Ma and McCormick's hybrid rendering ("wilson.*"): how the low-resolution
// volume is made, where its error earns a point, how points are stored and drawn, and how the work is
// spread over the machine. Each says where its value comes from: the paper (Wilson et al. 2002) or
// ours where the paper is silent.

#include "sim/core/config.h"
#include "sim/core/param.h"

#include <cstdint>
#include <limits>

namespace pp5 {

// How a low-resolution sample is made from the full-resolution voxels around it.
enum class Downsample {
    Cubic,    // Catmull-Rom tricubic interpolation at the sample's position (the paper's usual choice)
    Box,      // the mean of the k^3 voxels it stands for
    Minimum,  // the least voxel under its trilinear hat: the reconstruction never overestimates
};
// Which errors earn a point: either sign (the paper), or only where the low-resolution volume is
// too low (the only error an additive point can repair).
enum class ErrorSign { Magnitude, Positive };
// Who composites a slab's points: the renderers, one primitive each, or the GPs, sending the
// composited block of each (slab, brick) as pixels.
enum class WilsonPointPath { Renderer, GpSheets };
// How a slice's opacity is corrected for the distance a ray travels between slices.
enum class SliceOpacityCorrection { PerSlice, None };

struct WilsonSettings {
    int downsample_factor = 2;  // k: one low-resolution voxel per k^3 voxels
    Downsample downsample = Downsample::Cubic;
    double overestimate_limit = std::numeric_limits<double>::infinity();  // value units; inf: no limit
    int error_grid_factor = 1;                                            // error samples per voxel along each axis
    double error_threshold = 1.0 / 64.0;                                  // of the value range
    ErrorSign error_sign = ErrorSign::Magnitude;
    std::uint64_t max_points = 0;      // 0: every point past the threshold
    double point_overlap = 1.1;        // a point's side over the projected error-grid spacing
    double point_opacity_scale = 1.0;  // the paper's global point transparency
    WilsonPointPath point_path = WilsonPointPath::GpSheets;
    SliceOpacityCorrection opacity_correction = SliceOpacityCorrection::PerSlice;
    int brick_voxels = 16;      // edge of the low-resolution bricks dealt to GPs
    int accumulator_bits = 12;  // fraction bits of the renderers' colour and opacity

    static const ParamGroup& params();
    // Reads and checks the settings: a bad combination is an InputError naming the key.
    static WilsonSettings from(const MachineConfig& config);
};

}  // namespace pp5
