#pragma once
// Recorded work timed on a `uniprocessor` machine (Levoy's Sun 4/280, the host): one processor does
// every phase's work one step after another with all the data in its memory. A PP pass costs what the
// kernel says one processor would do instead (PpPhase::Pass::on_one_processor), a broadcast phase only
// its computing, a GP phase the operations of every task and item. There are no messages, caches or
// waits: each phase's time is a sum, at the processor's per-operation costs.

#include "sim/core/config.h"
#include "sim/timing/frame_timing.h"
#include "sim/timing/recorded_work.h"

namespace pp5 {

FrameTiming time_frame_on_one_processor(const MachineConfig& config, const FrameWork& work);

}  // namespace pp5
