#pragma once
// perm.shading = "pp": the renderers' pixel processors classify and shade PERM's records, so a GP's
// sample only reads a colour and an opacity. Each record's D^3 density positions become voxel slots
// (the voxel store's layout: value, gradient, colour, opacity; voxel_record.h) in the backing store of
// the renderer that holds the record, and Levoy's classification and shading programs run over them
// unchanged. A light or colour change reruns only the shading; a new classification rebuilds PERM.
//
// Records are packed, not laid out as the volume is, so the QEE cannot give a PP its position's place:
// the PPs shade for a distant viewer along the view's central direction (a headlight shines from it),
// as Levoy's PPs do for highlights under perspective, and the GPs depth-cue each sample, which they
// know the place of. The gradient at a density position is that of the gradient position whose
// sub-cube holds it (the same position when D = G).

#include "kernels/perm/perm_structure.h"
#include "kernels/shared/pp_volume/shading_programs.h"
#include "kernels/shared/pp_volume/voxel_record.h"
#include "scene/render/classification.h"
#include "scene/render/shading.h"
#include "sim/machine/machine.h"
#include "sim/timing/recorded_work.h"

#include <glm/vec4.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace pp5 {

class PermRecordShading {
public:
    // What the records take in each renderer's backing store: whole slots of `layout` bits per PP.
    static std::uint64_t backing_store_bits_needed(std::uint64_t positions_on_renderer, int pps,
                                                   const VoxelRecordLayout& layout);

    // Places every record's density positions on its renderer (renderer_of gives it per candidate)
    // and loads their values and gradients. Throws InputError (renderer.backing_store_bits) when they
    // do not fit.
    PermRecordShading(Machine& machine, const PermStructure& structure, glm::vec3 spacing,
                      const VoxelRecordLayout& layout,
                      const std::function<std::uint32_t(std::uint32_t candidate)>& renderer_of);

    // The programs' runs on every renderer, recorded; each leaves its results in the slots, and
    // read_back() copies them out for the GPs' look-ups.
    PpPassWork classify(const Classification& classification);
    PpPassWork shade(const ColorMap& colors, const PhongLighting& lighting, glm::vec3 view_forward);
    void read_back();

    // The colour and opacity the PPs left at a record's density position (after read_back).
    glm::vec4 at(std::uint32_t candidate, int position) const;
    // What one record takes on the ring and in a GP's cache: its positions' colours and opacities,
    // and their densities when the GPs depth-cue (the cue dims only the lit part, so the GP needs the
    // ambient part, from the density's base colour).
    std::uint32_t fetched_words(bool with_density) const;
    std::uint64_t positions() const { return positions_; }
    // The shading the PPs do: `lighting` without depth cueing (the GPs apply it).
    static PhongLighting lighting_on_pps(const PhongLighting& lighting);

private:
    PpPassWork run(const PpProgram& program);

    Machine& machine_;
    const PermStructure& structure_;
    glm::vec3 spacing_;
    VoxelRecordLayout layout_;
    VoxelQuantization quantization_;
    int per_record_;                                   // D^3
    std::vector<std::vector<std::uint32_t>> records_;  // per renderer, its candidates in order
    std::vector<int> slots_;                           // per renderer
    std::uint64_t positions_ = 0;
    std::vector<std::uint16_t> results_;  // per candidate and position: red, green, blue, opacity codes
};

}  // namespace pp5
