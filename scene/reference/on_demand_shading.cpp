#include "scene/reference/on_demand_shading.h"

#include <chrono>
#include <thread>

namespace pp5 {

OnDemandShading::OnDemandShading(ShadedVolume& shaded, const OccupancyGrid& occupancy)
    : shaded_(shaded),
      occupancy_(occupancy),
      last_block_(occupancy.block_dims() - 1),
      states_(new std::atomic<std::uint8_t>[occupancy.block_count()]) {
    invalidate();
}

void OnDemandShading::invalidate() {
    const glm::ivec3 blocks = occupancy_.block_dims();
    for (int z = 0; z < blocks.z; ++z) {
        for (int y = 0; y < blocks.y; ++y) {
            for (int x = 0; x < blocks.x; ++x) {
                const glm::ivec3 block{x, y, z};
                states_[occupancy_.block_index(block)].store(occupancy_.occupied(block) ? kToShade : kReady,
                                                             std::memory_order_relaxed);
            }
        }
    }
}

void OnDemandShading::shade_or_wait(glm::ivec3 block, const BlockShader& shader) {
    std::atomic<std::uint8_t>& state = states_[occupancy_.block_index(block)];
    std::uint8_t expected = kToShade;
    if (state.compare_exchange_strong(expected, kShading, std::memory_order_acquire)) {
        const auto start = std::chrono::steady_clock::now();
        voxels_shaded_.fetch_add(shader.shade(block, shaded_), std::memory_order_relaxed);
        const auto elapsed = std::chrono::steady_clock::now() - start;
        shading_nanoseconds_.fetch_add(
            static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count()),
            std::memory_order_relaxed);
        state.store(kReady, std::memory_order_release);
        return;
    }
    // Another thread is shading it: its writes become visible with the release store of kReady.
    while (state.load(std::memory_order_acquire) != kReady) std::this_thread::yield();
}

}  // namespace pp5
