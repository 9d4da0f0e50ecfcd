#include "kernels/perm/perm_settings.h"

#include "sim/core/input_error.h"

#include <string>

namespace pp5 {

namespace {
std::string paper(const char* where) { return std::string("Lim and Shin, PERM, ") + where; }
}  // namespace

const ParamGroup& PermSettings::params() {
    static const ParamGroup group = [] {
        ParamGroup g("perm",
                     "Lim and Shin's PERM: each non-transparent cell's density and gradient precomputed at quantized "
                     "positions, looked up by each ray sample instead of interpolated");
        g.integer("density_positions", 5, "per axis", 1, 16,
                  "D_Nqc: quantized density positions along each axis of a cell", Provenance::Paper,
                  paper("sections 4.1 and 6, Tables 1 and 2 (5)"))
            .integer("gradient_positions", 5, "per axis", 1, 16,
                     "G_Nqc: quantized gradient positions along each axis of a cell", Provenance::Paper,
                     paper("section 6, Table 2 (3)"))
            .text("positions", "centers", {"centers", "rounded", "paper"},
                  "Where the quantized values sit and how a sample finds one: at sub-cube centres (the sub-cube it is "
                  "in), at "
                  "k/N rounded as eq. (4) with the top clamped, or eq. (4) as printed (rounding past the last position "
                  "carries "
                  "into the next axis's digit)",
                  Provenance::Paper, paper("section 4.2, eq. (4) and Figure 3; eq. (4)'s carry is the paper's error"))
            .integer("qbm", 1000, "entries", 10, 100000, "QBM: entries of each axis's mapping table (M_LUT)",
                     Provenance::Paper, paper("Figure 3 (1000)"))
            .text("candidate_rule", "any_corner", {"any_corner", "paper_origin"},
                  "Which cells are candidates: any whose corners may be non-transparent (no surface is lost), or, as "
                  "eq. (1), "
                  "those whose origin voxel may be",
                  Provenance::Paper, paper("section 4.1, eq. (1)"))
            .integer("index_bytes", 2, "bytes", 2, 4,
                     "Bytes per index-volume entry: 2 holds per-slice indices with a 4-byte summed count per slice "
                     "(section 4.3), "
                     "4 holds indices directly",
                     Provenance::Paper, paper("section 4.3; Tables 1 and 2 match eq. (3) only with 2"))
            .text("residence", "renderers", {"renderers", "gp_memory"},
                  "Where the structure lives: the renderers' backing store, fetched by the GPs through their caches, "
                  "or a copy in "
                  "every GP's memory (when it fits)",
                  Provenance::Default,
                  "pp5sim: the records sit beside the voxels they were built from, as Levoy's voxels do")
            .text("shading", "gp", {"gp", "pp"},
                  "Who classifies and shades: the GPs at every sample from the looked-up density and gradient (the "
                  "paper), or "
                  "the renderers' PPs at every record position (voxel_store.* widths), leaving the GPs a colour and "
                  "opacity to "
                  "read and the depth cue; a light change then reshades on the PPs",
                  Provenance::Default,
                  "pp5sim: Levoy's division of labour applied to PERM's records; the paper shades per sample")
            .integer("tile_pixels", 16, "pixels", 2, 256, "Edge of the screen tiles dealt to GPs", Provenance::Default,
                     "pp5sim")
            .integer("reduction_cells", 0, "cells", 0, 1000,
                     "t_e: drop candidate cells more than this many cells deep inside opaque ones, seen from outside "
                     "the volume, "
                     "where no ray reaches them before terminating (0 keeps every candidate)",
                     Provenance::Paper, paper("section 5: properties (1) and (2), peeling to t >= t_e"))
            .real("reduction_opacity", 0.5, "opacity", 0.01, 1,
                  "alpha_e: a cell counts as opaque for the reduction when no sample in it can have less opacity",
                  Provenance::Default,
                  "pp5sim: the paper's 'fully opaque' is not defined; with it the reduction is safe when "
                  "(1 - alpha_e)^(t_e - 2) <= 1 - the termination opacity");
        return g;
    }();
    return group;
}

PermSettings PermSettings::from(const MachineConfig& config) {
    PermSettings s;
    s.density_positions = static_cast<int>(config.integer("perm.density_positions"));
    s.gradient_positions = static_cast<int>(config.integer("perm.gradient_positions"));
    const std::string positions = config.text("perm.positions");
    s.positions = positions == "paper"     ? QuantizedPositions::Paper
                  : positions == "rounded" ? QuantizedPositions::Rounded
                                           : QuantizedPositions::Centers;
    s.qbm = static_cast<int>(config.integer("perm.qbm"));
    s.candidates =
        config.text("perm.candidate_rule") == "paper_origin" ? CandidateRule::PaperOrigin : CandidateRule::AnyCorner;
    s.index_bytes = static_cast<int>(config.integer("perm.index_bytes"));
    if (s.index_bytes != 2 && s.index_bytes != 4)
        reject_field("perm.index_bytes", "must be 2 (per-slice indices and a summed table) or 4");
    s.residence = config.text("perm.residence") == "gp_memory" ? PermResidence::GpMemory : PermResidence::Renderers;
    s.shading = config.text("perm.shading") == "pp" ? PermShading::Pp : PermShading::Gp;
    if (s.shading == PermShading::Pp && s.residence == PermResidence::GpMemory)
        reject_field(
            "perm.shading",
            "the PPs can shade only records in the renderers' backing store; use perm.residence = \"renderers\"");
    s.tile_pixels = static_cast<int>(config.integer("perm.tile_pixels"));
    s.reduction_cells = static_cast<int>(config.integer("perm.reduction_cells"));
    s.reduction_opacity = config.real("perm.reduction_opacity");
    return s;
}

}  // namespace pp5
