#include "scene/reference/voxel_opacity.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <stdexcept>

namespace pp5 {

std::vector<float> classify_voxels(const Volume& volume, const GradientField& gradients,
                                   const Classification& classification) {
    if (gradients.dims != volume.dims()) throw std::invalid_argument("classify_voxels: gradients of another volume");
    std::vector<float> opacity(volume.voxel_count());
    const std::span<const float> values = volume.samples();
    const std::size_t slice = static_cast<std::size_t>(volume.dims().x) * static_cast<std::size_t>(volume.dims().y);
    pp5::parallel_for(tbb::blocked_range<int>(0, volume.dims().z), [&](const tbb::blocked_range<int>& slices) {
        const std::size_t begin = static_cast<std::size_t>(slices.begin()) * slice;
        const std::size_t end = static_cast<std::size_t>(slices.end()) * slice;
        for (std::size_t i = begin; i < end; ++i) {
            opacity[i] = classification.opacity(values[i], glm::length(gradients.at(i)));
        }
    });
    return opacity;
}

void scale_by_region(std::vector<float>& opacity, glm::ivec3 dims, const RegionOfInterest& region) {
    if (opacity.size() !=
        static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z))
        throw std::invalid_argument("scale_by_region: opacities of another volume");
    pp5::parallel_for(tbb::blocked_range<int>(0, dims.z), [&](const tbb::blocked_range<int>& slices) {
        for (int z = slices.begin(); z < slices.end(); ++z)
            for (int y = 0; y < dims.y; ++y) {
                const std::size_t row =
                    (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims.y) + static_cast<std::size_t>(y)) *
                    static_cast<std::size_t>(dims.x);
                for (int x = 0; x < dims.x; ++x) {
                    float& a = opacity[row + static_cast<std::size_t>(x)];
                    if (a > 0.0f) a = std::clamp(a * region.factor(glm::vec3(x, y, z)), 0.0f, 1.0f);
                }
            }
    });
}

void cap_gradients(const Volume& volume, const GradientField& gradients, const RegionOfInterest& region,
                   GradientField& capped) {
    capped.dims = gradients.dims;
    capped.gradients.resize(gradients.gradients.size());  // every voxel is written below
    const std::span<const float> values = volume.samples();
    const float air = volume.min_value();  // found once when the volume was made, not on each cap
    const glm::ivec3 dims = volume.dims();
    pp5::parallel_for(tbb::blocked_range<int>(0, dims.z), [&](const tbb::blocked_range<int>& slices) {
        for (int z = slices.begin(); z < slices.end(); ++z)
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x) {
                    const std::size_t i = volume.index(x, y, z);
                    capped.gradients[i] = region.capped_gradient(glm::vec3(x, y, z), values[i], gradients.at(i), air);
                }
    });
}

}  // namespace pp5
