#pragma once
// The parameters of Lim and Shin's PERM ("perm.*"): how finely each candidate cell is quantized for
// density and for the gradient, how a sample finds its quantized position, which cells are
// candidates, how the index volume is stored, and where the structure lives on the machine. Each says
// where its value comes from: the paper (Lim and Shin) or ours where the paper is silent or wrong.

#include "sim/core/config.h"
#include "sim/core/param.h"

namespace pp5 {

// Where a cell's quantized values sit and how a sample finds the nearest.
enum class QuantizedPositions {
    Centers,  // at the sub-cube centres (k + 1/2) / N; a sample takes the sub-cube it is in
    Rounded,  // at k / N, the nearest by eq. (4)'s rounding, the top position clamped to N - 1
    Paper,    // eq. (4) as printed: rounding up past the last position carries into the next axis
};
enum class CandidateRule {
    AnyCorner,    // a cell whose corners' value and gradient ranges may be non-transparent
    PaperOrigin,  // eq. (1): the cell's origin voxel may be non-transparent
};
enum class PermResidence { Renderers, GpMemory };
enum class PermShading {
    Gp,  // each sample classified and shaded on the GP from the looked-up values (the paper)
    Pp,  // the renderers' PPs classify and shade every record position; a sample reads colour and opacity
};

struct PermSettings {
    int density_positions = 5;   // D_Nqc: quantized positions per axis for the density
    int gradient_positions = 5;  // G_Nqc: ... for the gradient
    QuantizedPositions positions = QuantizedPositions::Centers;
    int qbm = 1000;  // entries of each axis's mapping table
    CandidateRule candidates = CandidateRule::AnyCorner;
    int index_bytes = 2;  // bytes per index-volume entry (2: per-slice indices and a summed table)
    PermResidence residence = PermResidence::Renderers;
    PermShading shading = PermShading::Gp;
    int tile_pixels = 16;            // edge of the screen tiles dealt to GPs
    int reduction_cells = 0;         // t_e: keep candidates at most this many opaque cells deep (0: keep all)
    double reduction_opacity = 0.5;  // alpha_e: a cell counts as opaque when no sample in it is below this

    static const ParamGroup& params();
    static PermSettings from(const MachineConfig& config);
};

}  // namespace pp5
