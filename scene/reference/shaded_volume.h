#pragma once
// Stage 3 of Levoy's pipeline: a colour and an opacity at every voxel, the input of the compositor.
// The simulated pixel processors produce the same thing in fixed point and feed it to the same
// compositor (composite.h).
//
// Which voxels are shaded: the compositor interpolates colour and opacity separately (Levoy's order),
// so the colour of a transparent voxel does enter a sample next to an opaque one; only voxels whose
// every neighbour is transparent can be left unshaded. shade_voxels shades every voxel of the
// occupied blocks of an OccupancyGrid (which contain all such neighbourhoods) and leaves the others at
// zero colour, whatever their opacity (which is zero there by construction).

#include "scene/reference/gradient_field.h"
#include "scene/reference/occupancy_grid.h"
#include "scene/reference/sample_shader.h"
#include "scene/reference/shading_view.h"
#include "scene/reference/voxel_bricks.h"
#include "scene/render/classification.h"
#include "scene/render/shading.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pp5 {

class PolygonMattes;

struct ShadedVolume {
    glm::ivec3 dims{0};
    glm::vec3 spacing{1.0f};
    std::vector<glm::vec4> rgba;  // Volume::index order; colour not premultiplied, alpha = opacity
};

// Shades the voxels of one block at a time: the unit of parallel and of on-demand shading (blocks own
// disjoint voxels, so blocks can be shaded concurrently). Holds references to its inputs.
class BlockShader {
public:
    // `bricks` and `brick_opacities` (the opacities gathered by bricks->gather), when given, supply the
    // same values, gradients and opacities block by block: the same colours, read faster.
    BlockShader(const Volume& volume, const GradientField& gradients, std::span<const float> opacities,
                const OccupancyGrid& occupancy, const ColorMap& color_map, const PhongLighting& lighting,
                const ShadingView& view, const VoxelBricks* bricks = nullptr,
                std::span<const float> brick_opacities = {}, const PolygonMattes* mattes = nullptr);

    // Writes colour and opacity of the block's voxels into `out`, with the polygons matted over them
    // when given; returns how many voxels.
    std::uint64_t shade(glm::ivec3 block, ShadedVolume& out) const;

    const OccupancyGrid& occupancy() const { return occupancy_; }

private:
    const Volume& volume_;
    const GradientField& gradients_;
    std::span<const float> opacities_;
    const OccupancyGrid& occupancy_;
    SampleShader shader_;
    const VoxelBricks* bricks_;
    std::span<const float> brick_opacities_;
    const PolygonMattes* mattes_;  // matted over each block once it is shaded (polygon_matte.h); may be null
};

// Shades the volume for one view. `opacities` from classify_voxels; `occupancy` from
// occupancy_from_opacity(opacities) — computed here when not given.
ShadedVolume shade_voxels(const Volume& volume, const GradientField& gradients, std::span<const float> opacities,
                          const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view,
                          const OccupancyGrid* occupancy = nullptr);
ShadedVolume shade_voxels(const Volume& volume, const GradientField& gradients, std::span<const float> opacities,
                          const ColorMap& color_map, const PhongLighting& lighting, const Camera& camera,
                          const OccupancyGrid* occupancy = nullptr);

// Reshades `shaded` in place for a new view or lighting: rewrites only the voxels of occupied blocks,
// saving the allocation and the pass over empty space. `shaded` must hold this volume's shading under
// the same opacities and occupancy (so the voxels outside occupied blocks are already right).
// Returns the number of voxels shaded.
std::uint64_t reshade_voxels(ShadedVolume& shaded, const Volume& volume, const GradientField& gradients,
                             std::span<const float> opacities, const OccupancyGrid& occupancy,
                             const ColorMap& color_map, const PhongLighting& lighting, const ShadingView& view);

}  // namespace pp5
