#pragma once
// Polygons scan-converted into the volume in floating point, the oracle of Levoy's 3D scan-conversion
// on the pixel processors (scene/render/polygon.h): each voxel's coverage is the fraction of many
// subvoxel sample points (kOracleSamples, against the machine's few) that lie in the polygon's
// one-voxel sheet, and the polygon is matted over the voxel's shaded colour and opacity as the PPs do,
// polygon by polygon in order:
//   a_p = coverage x polygon opacity,  a = a_p + a_v (1 - a_p),  c = (c_p a_p + c_v a_v (1 - a_p)) / a,
// with the polygon's colour and opacity (linear over its plane) taken at the voxel's centre. The mattes
// come after the region of interest has scaled the voxels' opacities, as on the machine.

#include "scene/reference/shaded_volume.h"
#include "scene/render/polygon.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace pp5 {

class PolygonMattes {
public:
    static constexpr int kOracleSamples = 256;

    PolygonMattes(glm::ivec3 dims, const std::vector<PolygonSpec>& polygons, int samples = kOracleSamples);

    bool empty() const { return by_block_.empty(); }
    std::size_t voxels_covered() const { return voxels_covered_; }
    // Raises each covered voxel's opacity to at least its polygons' coverage opacity: what empty-space
    // skipping must treat as non-empty (the shading itself keeps the classification's opacities).
    void mark_non_empty(std::vector<float>& opacity) const;
    // Mattes the polygons over the voxels of one OccupancyGrid block, already shaded into `shaded`.
    void apply(std::size_t block_index, ShadedVolume& shaded) const;

private:
    struct VoxelMatte {
        std::size_t voxel = 0;  // Volume::index order
        float opacity = 0.0f;   // a_p
        glm::vec3 color{0.0f};
    };
    std::unordered_map<std::size_t, std::vector<VoxelMatte>> by_block_;  // in polygon order within a block
    std::size_t voxels_covered_ = 0;
};

}  // namespace pp5
