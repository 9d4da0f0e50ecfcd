#include "kernels/reference/voxel_opacity.h"
#include "sim/core/parallel.h"

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>

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

}  // namespace pp5
