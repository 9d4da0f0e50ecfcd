#include "kernels/levoy/binary_pyramid.h"
#include "sim/core/parallel.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <array>
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
                const glm::ivec3 cell(x, y, z);
                level.words[brick_of(cell, level.bricks)] |= std::uint64_t{1} << in_brick(cell);
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
    pyramid.count_empty_levels();
    return pyramid;
}

namespace {
// Which of a brick's 2x2x2 parent cells each of its 4x4x4 cells lies in (bit index order: x, y, z).
constexpr std::array<std::uint8_t, 64> kParentOf = [] {
    std::array<std::uint8_t, 64> of{};
    for (int cell = 0; cell < 64; ++cell)
        of[static_cast<std::size_t>(cell)] =
            static_cast<std::uint8_t>(((cell & 3) >> 1) | ((((cell >> 2) & 3) >> 1) << 1) | (((cell >> 4) >> 1) << 2));
    return of;
}();
}  // namespace

void BinaryPyramid::count_empty_levels() {
    if (levels() < 2) return;
    // From the top down, a brick (one word of bits) at a time: a cell's count is 0 when it is occupied,
    // else one more than its parent's. Each level's counts are in bricks like its bits, so a brick's
    // 4x4x4 cells find their 2x2x2 parents in one brick of the level above.
    std::vector<std::uint8_t> above;  // the counts of the level above, by brick
    for (int l = levels() - 1; l >= 1; --l) {
        const Level& level = levels_[static_cast<std::size_t>(l)];
        const Level* parents = l + 1 < levels() ? &levels_[static_cast<std::size_t>(l) + 1] : nullptr;
        std::vector<std::uint8_t> here(level.words.size() * 64, 0);
        pp5::parallel_for(tbb::blocked_range<int>(0, level.bricks.z), [&](const tbb::blocked_range<int>& r) {
            for (int bz = r.begin(); bz != r.end(); ++bz)
                for (int by = 0; by < level.bricks.y; ++by)
                    for (int bx = 0; bx < level.bricks.x; ++bx) {
                        const glm::ivec3 brick(bx, by, bz);
                        std::uint8_t parent[8] = {};  // above the top: nothing
                        if (parents != nullptr)
                            for (int i = 0; i < 8; ++i) {
                                const glm::ivec3 p = brick * 2 + glm::ivec3(i & 1, (i >> 1) & 1, i >> 2);
                                if (p.x < parents->dims.x && p.y < parents->dims.y && p.z < parents->dims.z)
                                    parent[i] = above[brick_of(p, parents->bricks) * 64 +
                                                      static_cast<std::size_t>(in_brick(p))];
                            }
                        const std::size_t b = index_of(brick, level.bricks);
                        const std::uint64_t bits = level.words[b];
                        std::uint8_t* out = &here[b * 64];
                        for (int cell = 0; cell < 64; ++cell) {
                            const auto empty = static_cast<std::uint8_t>(((bits >> cell) & 1u) ^ 1u);
                            out[cell] = static_cast<std::uint8_t>(empty * (1 + parent[kParentOf[cell]]));
                        }
                    }
        });
        above = std::move(here);
    }
    climb_bricks_ = levels_[1].bricks;
    climb_ = std::move(above);
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
