#include "scene/reference/gradient_field.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <vector>

namespace pp5 {

GradientField compute_gradients(const Volume& volume) {
    const glm::ivec3 dims = volume.dims();
    GradientField field;
    field.dims = dims;
    field.gradients.resize(volume.voxel_count());
    const float* f = volume.samples().data();
    const std::size_t row = static_cast<std::size_t>(dims.x);
    const std::size_t slice = row * static_cast<std::size_t>(dims.y);

    pp5::parallel_for(tbb::blocked_range<int>(0, dims.z), [&](const tbb::blocked_range<int>& slices) {
        for (int z = slices.begin(); z != slices.end(); ++z) {
            const std::size_t z_lo = static_cast<std::size_t>(std::max(z - 1, 0)) * slice;
            const std::size_t z_hi = static_cast<std::size_t>(std::min(z + 1, dims.z - 1)) * slice;
            for (int y = 0; y < dims.y; ++y) {
                const std::size_t y_lo = static_cast<std::size_t>(std::max(y - 1, 0)) * row;
                const std::size_t y_hi = static_cast<std::size_t>(std::min(y + 1, dims.y - 1)) * row;
                const std::size_t here = volume.index(0, y, z);
                for (int x = 0; x < dims.x; ++x) {
                    const std::size_t x_lo = static_cast<std::size_t>(std::max(x - 1, 0));
                    const std::size_t x_hi = static_cast<std::size_t>(std::min(x + 1, dims.x - 1));
                    const std::size_t xs = static_cast<std::size_t>(x);
                    const std::size_t yz = static_cast<std::size_t>(y) * row + static_cast<std::size_t>(z) * slice;
                    const std::size_t xz = xs + static_cast<std::size_t>(z) * slice;
                    const std::size_t xy = xs + static_cast<std::size_t>(y) * row;
                    field.gradients[here + xs] =
                        0.5f * glm::vec3(f[yz + x_hi] - f[yz + x_lo], f[xz + y_hi] - f[xz + y_lo],
                                         f[xy + z_hi] - f[xy + z_lo]);
                }
            }
        }
    });
    return field;
}

float largest_gradient_component(const Volume& volume) {
    const glm::ivec3 dims = volume.dims();
    std::vector<float> per_slice(static_cast<std::size_t>(dims.z), 0.0f);
    pp5::parallel_for(tbb::blocked_range<int>(0, dims.z), [&](const tbb::blocked_range<int>& slices) {
        for (int z = slices.begin(); z != slices.end(); ++z) {
            float largest = 0.0f;
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x) {
                    const glm::vec3 g = glm::abs(central_difference(volume, {x, y, z}));
                    largest = std::max({largest, g.x, g.y, g.z});
                }
            per_slice[static_cast<std::size_t>(z)] = largest;
        }
    });
    return per_slice.empty() ? 0.0f : *std::max_element(per_slice.begin(), per_slice.end());
}

}  // namespace pp5
