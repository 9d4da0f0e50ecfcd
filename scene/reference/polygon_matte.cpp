#include "scene/reference/polygon_matte.h"

#include "scene/reference/occupancy_grid.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pp5 {

PolygonMattes::PolygonMattes(glm::ivec3 dims, const std::vector<PolygonSpec>& polygons, int samples) {
    const std::vector<glm::dvec3> offsets = subvoxel_offsets(samples);
    const OccupancyGrid blocks(dims);  // for its block numbering, the one BlockShader::shade applies by
    const auto index = [&](glm::ivec3 v) {
        return static_cast<std::size_t>(v.x) +
               static_cast<std::size_t>(dims.x) *
                   (static_cast<std::size_t>(v.y) + static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(v.z));
    };
    const auto block_of = [&](glm::ivec3 v) { return blocks.block_index(v / OccupancyGrid::kBlockSize); };
    // A sample point reaches at most half a voxel's diagonal from the centre; the sheet is half a voxel thick.
    const double reach = 0.5 + std::sqrt(3.0) / 2.0;
    for (const PolygonSpec& spec : polygons) {
        const PreparedPolygon polygon = prepare_polygon(spec);
        if (polygon.degenerate) continue;
        const glm::ivec3 lo = glm::max(glm::ivec3(glm::floor(polygon.lower)) - 1, glm::ivec3(0));
        const glm::ivec3 hi = glm::min(glm::ivec3(glm::ceil(polygon.upper)) + 1, dims - 1);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) {
                    const glm::dvec3 centre(x, y, z);
                    if (std::abs(polygon.distance(centre)) > reach) continue;
                    int inside = 0;
                    for (const glm::dvec3& o : offsets) inside += polygon.in_sheet(centre + o);
                    if (inside == 0) continue;
                    const glm::vec3 p(centre);
                    const float coverage = static_cast<float>(inside) / static_cast<float>(offsets.size());
                    const float opacity = std::clamp(polygon.opacity(p), 0.0f, 1.0f) * coverage;
                    const glm::vec3 color =
                        glm::clamp(glm::vec3(polygon.red(p), polygon.green(p), polygon.blue(p)), 0.0f, 1.0f);
                    by_block_[block_of({x, y, z})].push_back({index({x, y, z}), opacity, color});
                    ++voxels_covered_;
                }
    }
}

void PolygonMattes::mark_non_empty(std::vector<float>& opacity) const {
    for (const auto& [block, mattes] : by_block_)
        for (const VoxelMatte& m : mattes) opacity[m.voxel] = std::max(opacity[m.voxel], m.opacity);
}

void PolygonMattes::apply(std::size_t block_index, ShadedVolume& shaded) const {
    const auto it = by_block_.find(block_index);
    if (it == by_block_.end()) return;
    for (const VoxelMatte& m : it->second) {
        glm::vec4& voxel = shaded.rgba[m.voxel];
        const float below = voxel.a * (1.0f - m.opacity);
        const float alpha = m.opacity + below;
        if (alpha > 0.0f) voxel = glm::vec4((m.color * m.opacity + glm::vec3(voxel) * below) / alpha, alpha);
    }
}

}  // namespace pp5
