#include "kernels/levoy/voxel_blocks.h"

#include <glm/common.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pp5 {

namespace {
constexpr std::uint32_t kMostBlocks = std::numeric_limits<std::uint32_t>::max();  // block numbers are 32-bit
}

VoxelBlocks::VoxelBlocks(const VoxelPlacement& placement, int block_cells, int voxel_bits)
    : placement_(placement), block_cells_(block_cells), voxel_bits_(voxel_bits) {
    if (block_cells < 1 || voxel_bits < 1) throw std::invalid_argument("voxel blocks: sizes must be positive");
    const glm::ivec3 cells = placement.volume_dims() - 1;
    blocks_ = (glm::max(cells, glm::ivec3(1)) + block_cells - 1) / block_cells;
    const auto count = block_count();
    if (count >= kMostBlocks) throw std::invalid_argument("voxel blocks: too many blocks; use larger ones");
    const glm::ivec3 stride{1, blocks_.x, blocks_.x * blocks_.y};
    std::vector<std::uint32_t>* parts[3] = {&x_part_, &y_part_, &z_part_};
    for (int a = 0; a < 3; ++a) {
        parts[a]->resize(static_cast<std::size_t>(std::max(cells[a], 1)));
        for (int c = 0; c < std::max(cells[a], 1); ++c)
            (*parts[a])[static_cast<std::size_t>(c)] = static_cast<std::uint32_t>((c / block_cells) * stride[a]);
    }
}

std::uint64_t VoxelBlocks::block_bits() const {
    const auto side = static_cast<std::uint64_t>(block_cells_ + 1);
    return side * side * side * static_cast<std::uint64_t>(voxel_bits_);
}

std::shared_ptr<const BlockDirectory> VoxelBlocks::directory() const {
    std::vector<std::uint32_t> first{0};
    std::vector<BlockPart> all;
    const int columns = placement_.shape().columns;
    const int rows = placement_.shape().rows;
    std::vector<BlockPart> by_renderer;  // few entries: a linear search beats a map
    for (std::uint64_t block = 0; block < block_count(); ++block) {
        const auto bx = static_cast<std::uint64_t>(blocks_.x);
        const auto by = static_cast<std::uint64_t>(blocks_.y);
        const glm::ivec3 b{static_cast<int>(block % bx), static_cast<int>(block / bx % by),
                           static_cast<int>(block / (bx * by))};
        const glm::ivec3 lo = b * block_cells_;
        const glm::ivec3 hi = glm::min(lo + block_cells_, placement_.volume_dims() - 1);  // inclusive
        // Within one z and one tile of PP columns x rows, every voxel is on the same renderer.
        by_renderer.clear();
        for (int z = lo.z; z <= hi.z; ++z) {
            for (int y = lo.y; y <= hi.y; y = (y / rows + 1) * rows) {
                const int y_end = std::min(hi.y + 1, (y / rows + 1) * rows);
                for (int x = lo.x; x <= hi.x; x = (x / columns + 1) * columns) {
                    const int x_end = std::min(hi.x + 1, (x / columns + 1) * columns);
                    const auto renderer = static_cast<std::uint32_t>(placement_.locate({x, y, z}).renderer);
                    const auto voxels = static_cast<std::uint32_t>((x_end - x) * (y_end - y));
                    const auto it = std::find_if(by_renderer.begin(), by_renderer.end(),
                                                 [&](const BlockPart& p) { return p.renderer == renderer; });
                    if (it == by_renderer.end()) by_renderer.push_back(BlockPart{renderer, voxels});
                    else it->units += voxels;
                }
            }
        }
        std::sort(by_renderer.begin(), by_renderer.end(),
                  [](const BlockPart& p, const BlockPart& q) { return p.renderer < q.renderer; });
        all.insert(all.end(), by_renderer.begin(), by_renderer.end());
        first.push_back(static_cast<std::uint32_t>(all.size()));
    }
    return std::make_shared<const BlockDirectory>(block_bits(), static_cast<std::uint32_t>(voxel_bits_),
                                                  std::move(first), std::move(all));
}

}  // namespace pp5
