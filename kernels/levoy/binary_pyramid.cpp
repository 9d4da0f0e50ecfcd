#include "kernels/levoy/binary_pyramid.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace pp5 {

namespace {
std::size_t index_of(glm::ivec3 p, glm::ivec3 dims) {
    return static_cast<std::size_t>(p.x) +
           static_cast<std::size_t>(dims.x) *
               (static_cast<std::size_t>(p.y) + static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(p.z));
}
}  // namespace

BinaryPyramid::Level BinaryPyramid::pack(glm::ivec3 dims, const std::vector<std::uint8_t>& bytes) {
    Level level;
    level.dims = dims;
    level.bricks = (dims + 3) / 4;
    level.words.assign(static_cast<std::size_t>(level.bricks.x) * static_cast<std::size_t>(level.bricks.y) *
                           static_cast<std::size_t>(level.bricks.z),
                       0);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                if (bytes[index_of({x, y, z}, dims)] == 0) continue;
                const std::size_t word = index_of({x >> 2, y >> 2, z >> 2}, level.bricks);
                level.words[word] |= std::uint64_t{1} << ((x & 3) | ((y & 3) << 2) | ((z & 3) << 4));
                ++level.occupied;
            }
    return level;
}

BinaryPyramid BinaryPyramid::from_opacity(const ShadedCodes& volume, const ShadedCodes* also) {
    const glm::ivec3 dims = volume.dims();
    if (also != nullptr && also->dims() != dims)
        throw std::invalid_argument("pyramid: the second volume has another size");
    if (dims.x < 2 || dims.y < 2 || dims.z < 2)
        throw std::invalid_argument("pyramid: a volume needs two voxels along each axis");
    BinaryPyramid pyramid;
    struct {
        glm::ivec3 dims;
        std::vector<std::uint8_t> bits;
    } base;
    base.dims = dims - 1;
    base.bits.assign(static_cast<std::size_t>(base.dims.x) * static_cast<std::size_t>(base.dims.y) *
                         static_cast<std::size_t>(base.dims.z),
                     0);
    // A voxel row's non-empty flags, ORed with the next voxel's: the x extent of each cell.
    pp5::parallel_for(tbb::blocked_range<int>(0, base.dims.z), [&](const tbb::blocked_range<int>& r) {
        std::vector<std::uint8_t> row(static_cast<std::size_t>(dims.x));
        for (int z = r.begin(); z != r.end(); ++z) {
            for (int y = 0; y < base.dims.y; ++y) {
                std::fill(row.begin(), row.end(), 0);
                for (int dz = 0; dz < 2; ++dz) {
                    for (int dy = 0; dy < 2; ++dy) {
                        const std::size_t start = index_of({0, y + dy, z + dz}, dims);
                        for (int x = 0; x < dims.x; ++x) {
                            const std::size_t i = start + static_cast<std::size_t>(x);
                            if (!volume.transparent(i) || (also != nullptr && !also->transparent(i)))
                                row[static_cast<std::size_t>(x)] = 1;
                        }
                    }
                }
                std::uint8_t* out = &base.bits[index_of({0, y, z}, base.dims)];
                for (int x = 0; x < base.dims.x; ++x)
                    out[x] = static_cast<std::uint8_t>(row[static_cast<std::size_t>(x)] |
                                                       row[static_cast<std::size_t>(x) + 1]);
            }
        }
    });
    pyramid.levels_.push_back(pack(base.dims, base.bits));
    auto below = std::move(base);
    while (below.dims != glm::ivec3(1)) {
        decltype(below) up;
        up.dims = (below.dims + 1) / 2;
        up.bits.assign(static_cast<std::size_t>(up.dims.x) * static_cast<std::size_t>(up.dims.y) *
                           static_cast<std::size_t>(up.dims.z),
                       0);
        for (int z = 0; z < below.dims.z; ++z)
            for (int y = 0; y < below.dims.y; ++y)
                for (int x = 0; x < below.dims.x; ++x)
                    if (below.bits[index_of({x, y, z}, below.dims)] != 0)
                        up.bits[index_of({x / 2, y / 2, z / 2}, up.dims)] = 1;
        pyramid.levels_.push_back(pack(up.dims, up.bits));
        below = std::move(up);
    }
    return pyramid;
}

std::uint64_t BinaryPyramid::cells(int level) const {
    const glm::ivec3 d = levels_.at(static_cast<std::size_t>(level)).dims;
    return static_cast<std::uint64_t>(d.x) * static_cast<std::uint64_t>(d.y) * static_cast<std::uint64_t>(d.z);
}

std::uint64_t BinaryPyramid::occupied_cells(int level) const {
    return levels_.at(static_cast<std::size_t>(level)).occupied;
}

std::uint64_t BinaryPyramid::total_cells() const {
    std::uint64_t n = 0;
    for (int l = 0; l < levels(); ++l) n += cells(l);
    return n;
}

std::uint64_t BinaryPyramid::total_cells_of(glm::ivec3 voxel_dims) {
    std::uint64_t n = 0;
    glm::ivec3 d = voxel_dims - 1;  // level 0: a cell between each pair of voxel planes
    for (;;) {
        n += static_cast<std::uint64_t>(d.x) * static_cast<std::uint64_t>(d.y) * static_cast<std::uint64_t>(d.z);
        if (d == glm::ivec3(1)) return n;
        d = (d + 1) / 2;
    }
}

bool BinaryPyramid::same_cells(const BinaryPyramid& other) const {
    return !levels_.empty() && !other.levels_.empty() && levels_.front().dims == other.levels_.front().dims &&
           levels_.front().words == other.levels_.front().words;
}

}  // namespace pp5
