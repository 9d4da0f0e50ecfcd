#pragma once
// The timing layer of Levoy's ray caster: replays the rays' recorded work (ray_caster.h) on the
// simulated machine, event by event.
//
// Each GP works through its tile tasks (a tile's rays of one refinement pass), keeping up to
// gp.ray_contexts rays in flight. It runs one ray until the ray needs a block that is not in its cache;
// then it asks the renderers holding that block's voxels (one request per renderer, over the ring),
// parks the ray and switches to another ready ray or starts a new one. A ray whose block is already on
// its way waits for it without asking again. The GP takes replies in when it next switches rays (the
// i860 polls its ring interface), stores the block in its cache and readies the rays that wait for it.
// When a tile's rays are done the GP fills the tile's other pixels by interpolation and sends the
// tile's pixels to the frame buffer; a refinement pass is complete when its last tile has arrived.
// A pass's rays depend on the colours of the pass before, across tiles, so no GP starts a task of a
// pass until every task of the passes before has finished (the colours themselves are not charged as
// messages). A GP with replies or a task on the way stops at its next switch to take them in.
//
// Renderers answer requests one at a time, after the PP passes of the frame, at
// renderer.request_* cost. Tiles go to GPs either statically (tile t to GP t mod G, every pass) or from
// a work queue at the host, which a GP asks over the ring whenever it runs out of tiles.
//
// A watchdog checks the run: if events run out while a GP still has work, or the frame runs past a
// limit, it stops with an error that names the GP and the block it is stuck on.

#include "kernels/levoy/ray_caster.h"
#include "kernels/levoy/voxel_blocks.h"
#include "sim/core/time.h"
#include "sim/machine/machine.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pp5 {

enum class RayAssignment { StaticTiles, WorkQueue };
std::string to_string(RayAssignment assignment);

// One tile's share of one refinement pass.
struct TileTask {
    int pass = 0;
    int tile = 0;
    std::uint32_t first_ray = 0;  // into the pass's CastBatch, whose rays are grouped by tile
    std::uint32_t ray_count = 0;
    std::uint32_t squares_tested = 0;  // refinement decisions made before casting
    std::uint32_t pixels_filled = 0;   // pixels interpolated after casting
    std::uint32_t tile_pixels = 0;     // pixels sent to the frame buffer
};

struct RayCastJob {
    std::vector<CastBatch> passes;
    std::vector<TileTask> tasks;  // ordered by pass, then tile
    int tiles = 0;
};

struct RayCastTimingOptions {
    RayAssignment assignment = RayAssignment::StaticTiles;
    int pixel_bits = 24;               // per pixel sent to the frame buffer
    int request_bits = 64;             // a request's payload: block number and return address
    Tick watchdog_limit = 1000 * kTicksPerSecond;  // a frame longer than this is a stall
};

// What the ray casting of one frame did, summed over the GPs.
struct RayCastReport {
    Tick start = 0;
    Tick end = 0;
    std::vector<Tick> pass_end;  // when each refinement pass's last tile reached the frame buffer
    std::uint64_t rays = 0;
    std::uint64_t samples = 0;
    std::uint64_t samples_skipped = 0;
    std::uint64_t pyramid_steps = 0;
    std::uint64_t rays_terminated = 0;
    std::uint64_t pixels_filled = 0;
    std::uint64_t cache_hits = 0;
    std::uint64_t cache_misses = 0;
    std::uint64_t requests = 0;            // messages to renderers
    std::uint64_t context_switches = 0;
    Tick gp_busy = 0;                       // summed over GPs
    Tick gp_wait = 0;                       // summed over GPs: work left, nothing to run (voxels or the next pass)
    Tick renderer_busy = 0;                 // answering requests, summed over renderers
    Tick ring_busy = 0;                     // summed over channels
    std::uint64_t events = 0;
};

// Runs `job` on `machine` from `start` (after whatever the renderers are already doing) and returns
// what it did. GP caches are used and left as they are. Throws std::runtime_error from the watchdog,
// after dropping the machine's pending events.
RayCastReport time_ray_casting(Machine& machine, VoxelBlocks& blocks, const RayCastJob& job,
                               const RayCastTimingOptions& options, Tick start);

}  // namespace pp5
