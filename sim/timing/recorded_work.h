#pragma once
// Recorded work: what a kernel asks of the machine in one frame, in the machine's own vocabulary, and
// independent of every timing parameter (costs, clocks, GP count, ring, caches). A kernel's functional
// layer computes the frame's real results and records this; the timing engine (frame_engine.h) replays
// it on any machine, and a uniprocessor sums it (one_processor.h). Calibration and sweeps re-time the
// same record on many machines without computing the frame again.
//
// A frame is a list of phases, each starting when the one before has ended:
//   - PpPhase: PP programs over voxel slots on the renderers, each pass after a command the host may
//     broadcast first (the QEE coefficients of a polygon, say);
//   - BroadcastPhase: every renderer broadcasts messages to every GP, and each GP, having taken them
//     all in, computes (the GPs build a shared data structure from the renderers' data);
//   - GpPhase: tasks for the GPs, each a list of items (a ray, a primitive batch) run in ray contexts
//     as steps of operations and fetches of blocks from the renderers through the GP's cache, ending
//     with pixels sent to the frame buffer. Tasks are in groups: a group's tasks start only when every
//     task of the groups before has run its items (refinement passes). A task may instead end by
//     sending primitive batches to renderers that own regions of the screen (sort-middle): each
//     renderer then works through its own list of region steps in order, each waiting for the batch it
//     draws, and finally sends its region's pixels to the frame buffer.
// GP operations are kinds the kernel declares (GpOpKind), each costed as a sum of cost parameters the
// kernel declares too ("gp_cost.<kernel>.*", in flops or cycles); the machine adds its own costs for
// messages, cache look-ups and context switches.

#include "sim/core/time.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_program.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace pp5 {

// An operation kind a kernel's GPs perform: its name ("levoy.sample") and the cost parameters whose
// sum is one operation's cost (keys of the machine configuration, each in flops or cycles).
struct GpOpKind {
    std::string name;
    std::vector<std::string> cost_keys;
};

// `count` operations of kind `kind` (an index into FrameWork::op_kinds).
struct GpOp {
    std::uint32_t kind = 0;
    std::uint32_t count = 0;
};
// Appends `count` operations of `kind` (none when 0), in as many GpOps as a 32-bit count needs.
void append_ops(std::vector<GpOp>& ops, std::uint32_t kind, std::uint64_t count);

// A kernel's PP program over slots of every renderer: the program, and per renderer how many slots it
// ran over and what it did there (from the functional run, so instruction counts are real). Passes
// may share one program (a mesh's triangles of one shape), which a frame then keeps once.
struct PpPassWork {
    std::shared_ptr<const PpProgram> program;
    std::vector<std::uint64_t> slots;  // per renderer
    std::vector<PpRunCounts> counts;   // per renderer
};

struct PpPhase {
    struct Pass {
        PpPassWork work;
        std::uint64_t command_bits = 0;      // broadcast by the host before the pass (0: none)
        std::vector<GpOp> on_one_processor;  // the same work done by a lone processor (a uniprocessor machine)
    };
    std::vector<Pass> passes;  // each renderer runs them in order, each once its command has arrived
};

struct BroadcastPhase {
    std::vector<std::uint32_t> messages_per_renderer;  // each renderer broadcasts this many
    std::uint64_t bits_per_message = 0;
    std::vector<GpOp> then_each_gp;  // what every GP computes once it has them all
};

// Which renderers hold a block's data, and how many units (voxels, say) each sends back.
struct BlockPart {
    std::uint32_t renderer = 0;
    std::uint32_t units = 0;
};

// The blocks a kernel's GPs fetch: each block's parts, the bits of one unit on the ring, and the bits a
// whole block takes in a GP's cache.
class BlockDirectory {
public:
    BlockDirectory(std::uint64_t block_bits, std::uint32_t unit_bits, std::vector<std::uint32_t> first_part,
                   std::vector<BlockPart> parts);
    std::uint64_t block_bits() const { return block_bits_; }
    std::uint32_t unit_bits() const { return unit_bits_; }
    std::uint64_t block_count() const { return first_part_.size() - 1; }
    std::span<const BlockPart> parts(std::uint64_t block) const {
        return {parts_.data() + first_part_[block], first_part_[block + 1] - first_part_[block]};
    }

private:
    std::uint64_t block_bits_;
    std::uint32_t unit_bits_;
    std::vector<std::uint32_t> first_part_;  // block_count + 1 entries
    std::vector<BlockPart> parts_;
};

inline constexpr std::uint32_t kNoFetch = std::numeric_limits<std::uint32_t>::max();

// Operations, then a fetch of `block` through the cache (kNoFetch: none).
struct GpStep {
    std::uint32_t first_op = 0;  // into GpPhase::ops
    std::uint32_t op_count = 0;
    std::uint32_t block = kNoFetch;
};

// One unit of work that runs in a ray context: its steps in order.
struct GpItem {
    std::uint32_t first_step = 0;  // into GpPhase::steps
    std::uint32_t step_count = 0;
};

// Pixels of the picture, for a task that is a screen tile (width 0: it is not).
struct ScreenRect {
    std::uint16_t x = 0, y = 0, width = 0, height = 0;
};

struct GpTask {
    std::uint32_t group = 0;                       // groups run in order (refinement passes)
    std::uint32_t key = 0;                         // static assignment gives the task to GP key mod G (a tile's number)
    std::uint32_t first_item = 0, item_count = 0;  // into GpPhase::items
    std::uint32_t first_op = 0, op_count = 0;      // before its items (deciding what to cast)
    std::uint32_t first_finish_op = 0, finish_op_count = 0;  // after its last item (filling pixels)
    std::uint32_t pixels = 0;                                // then sent to the frame buffer (0: nothing is sent)
    std::uint32_t first_batch = 0, batch_count = 0;          // then sent to renderers, in order (GpPhase::batches)
    ScreenRect screen;  // the tile it casts, if it is one (for a map of which GP cast what)
};

// A message of primitives (or a block of pixels) a GP sends to the renderer that owns part of the screen.
struct PrimitiveBatch {
    std::uint32_t renderer = 0;
    std::uint64_t bits = 0;  // payload on the ring
};

inline constexpr std::uint32_t kNoBatch = std::numeric_limits<std::uint32_t>::max();

// One step of a renderer's screen work: once batch `batch` has arrived (kNoBatch: nothing to wait
// for), the controller writes `write_words` of its words into the PPs, then runs region program
// `program` `runs` times over the whole array (one run per primitive).
struct RegionStep {
    std::uint32_t batch = kNoBatch;
    std::uint32_t program = 0;  // into GpPhase::region_programs
    std::uint32_t runs = 0;
    std::uint64_t write_words = 0;
};

// A renderer's screen work in a GP phase, in the order it must be done (the order that makes the
// picture), then the pixels it sends to the frame buffer.
struct RegionWork {
    std::vector<RegionStep> steps;
    std::uint64_t readout_pixels = 0;
};

enum class TaskAssignment { Static, WorkQueue };
std::string to_string(TaskAssignment assignment);

struct GpPhase {
    std::vector<GpOp> ops;
    std::vector<GpStep> steps;
    std::vector<GpItem> items;
    std::vector<GpTask> tasks;  // in group order
    std::uint32_t groups = 0;
    TaskAssignment assignment = TaskAssignment::Static;
    std::shared_ptr<const BlockDirectory> blocks;  // for the fetches (none needed when no step fetches)
    std::uint32_t fetch_request_bits = 64;         // a request's payload: block number and return address
    // Sort-middle screen work (empty when the GPs send pixels themselves):
    std::vector<PrimitiveBatch> batches;
    std::vector<PpProgram> region_programs;
    std::vector<RegionWork> regions;             // per renderer
    std::vector<GpOp> regions_on_one_processor;  // the renderers' screen work done by a lone processor
};

struct Phase {
    std::string name;  // "shading", "pyramid", "ray_casting": how the timing names it
    std::variant<PpPhase, BroadcastPhase, GpPhase> work;
};

struct FrameWork {
    std::vector<GpOpKind> op_kinds;
    std::vector<Phase> phases;
    bool invalidate_gp_caches = false;  // the data the GPs cached has changed
    // The data changed, but as the frame's first GP phase begins each GP asks again for the blocks it
    // used in the frame before (what it will need again while the view stays), in the order it first
    // used them and a few blocks a message, instead of asking for each when a ray first misses it. The
    // rest of its cache is dropped.
    bool refresh_gp_caches = false;
    // How many blocks one refresh message asks for: a renderer answers its requests in the order they
    // come, so smaller messages let every GP's first blocks come back early.
    std::uint32_t refresh_blocks_per_message = 16;
    std::uint64_t gp_resident_bits = 0;  // what each GP keeps besides its cache (checked against gp.memory_bytes)
    // Data a GP keeps for each task key it owns (static assignment: GP key mod G), on top of the above.
    std::vector<std::uint64_t> resident_bits_by_key;
    int image_width = 0;  // the picture the frame buffer receives (checked against its size)
    int image_height = 0;
};

}  // namespace pp5
