#pragma once
// The timing engine: replays any kernel's recorded frame (recorded_work.h) on the machine's
// components, in one event loop, phase after phase.
//
// PP phases run each pass on every renderer's clock (Renderer::begin_pass), after the host's command
// has crossed the ring. A broadcast phase streams each renderer's messages over the ring to every GP,
// which takes each in after the one before and then computes. A GP phase runs tasks on the GPs:
//   - each GP keeps up to gp.ray_contexts items in flight; it runs one until a step needs a block its
//     cache lacks, asks the renderers holding the block's parts (a request each, over the ring), parks
//     the item and switches to another ready one or starts a new one. An item whose block is already on
//     its way waits for it without asking again;
//   - the GP takes replies in at its next switch (the i860 polls its ring interface), stores the block
//     in its cache and readies the items waiting for it;
//   - renderers answer requests one at a time, behind their PP passes;
//   - when a task's items are done the GP runs the task's finishing operations and sends its pixels to
//     the frame buffer, which counts them; a group's end is when its last pixels arrive;
//   - tasks go to GPs statically (key mod G) or from a work queue at the host, asked over the ring.
// A watchdog covers the whole frame: if events run out with work left, or the frame passes a limit, it
// stops with an error that names the phase, the GP, the item and the block it is stuck on.

#include "sim/machine/machine.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

namespace pp5 {

struct EngineOptions {
    Tick watchdog_limit = 1000 * kTicksPerSecond;  // a frame longer than this is a stall
};

// Times `work` on `machine` from its current time; GP caches carry over from frame to frame unless the
// work invalidates them. Throws InputError when the machine cannot hold what the frame needs (the
// frame buffer too small for the image, a GP's memory too small for its cache and resident data, a
// cache smaller than one block), and std::runtime_error from the watchdog (pending events dropped).
FrameTiming time_frame(Machine& machine, const FrameWork& work, const EngineOptions& options = {});

// InputError naming frame_buffer.width or .height when a picture of that size does not fit the frame
// buffer (time_frame checks every frame; a frontend can ask before any work).
void check_picture_fits(const Machine& machine, int width, int height);

// InputError naming gp.memory_bytes when a GP cannot hold its block cache (when `with_cache`) plus
// `resident_bits` of the kernel's data and its share of `resident_bits_by_key` (key k on GP k mod the
// GP count). time_frame checks every frame; a kernel can ask before any work, from what it knows its
// frames will keep.
void check_gp_memory_fits(const Machine& machine, bool with_cache, std::uint64_t resident_bits,
                          const std::vector<std::uint64_t>& resident_bits_by_key = {});

// The cost of one operation of each of `kinds` on a GP of `config`, in picoseconds: the sum of its
// cost parameters, each at the GP's flop rate or clock (per its unit), times the calibration scales.
std::vector<Tick> gp_op_costs(const MachineConfig& config, const std::vector<GpOpKind>& kinds);

}  // namespace pp5
