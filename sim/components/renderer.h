#pragma once
// A renderer: a SIMD array of bit-serial pixel processors (PPs), each with a little local memory and a
// larger backing store, driven by a controller and a quadratic expression evaluator. Kernels give it PP
// programs to run over the data its PPs hold (in Levoy's design, the voxels: classified and shaded in
// parallel) and blocks of that data for the GPs to fetch.
//
// Function and time are kept apart: the PP array (sim/pixel_processors/pp_array.h) computes real values, and
// this component spends simulated time on the program runs it is given, at the cost the PP cost model
// puts on them (sim/pixel_processors/pp_cost_model.h); an event marks the end of each pass.

#include "sim/core/clock_domain.h"
#include "sim/core/component.h"
#include "sim/core/config.h"
#include "sim/core/event_queue.h"
#include "sim/core/trace_recorder.h"
#include "sim/pixel_processors/pp_array.h"
#include "sim/pixel_processors/pp_cost_model.h"

#include <memory>
#include <string>

namespace pp5 {

// One program run over a number of voxel slots, as the controller would sequence it.
struct RendererPass {
    std::string program;
    PpProgramCost cost;       // of one slot
    std::uint64_t slots = 0;  // slots run, one after another
    PpRunCounts counts;       // over all slots, from the functional run
    int local_memory_bits_used = 0;
};

class Renderer : public Component, private EventHandler {
public:
    static const ParamGroup& params();

    Renderer(std::size_t index, const MachineConfig& config);

    std::size_t index() const { return index_; }
    const ClockDomain& clock() const { return clock_; }
    std::uint64_t pixel_processors() const { return columns_ * rows_; }
    int columns() const { return static_cast<int>(columns_); }
    int rows() const { return static_cast<int>(rows_); }
    std::uint64_t local_memory_bits() const { return local_memory_bits_; }
    std::uint64_t backing_store_bits() const { return backing_store_bits_; }
    const PpCostModel& cost_model() const { return cost_model_; }

    // The PPs' functional state, allocated on first use (a run that never uses the PPs pays nothing).
    PpArray& array();

    // Starts `pass` at `start` (or when the renderer is next free, if later); returns when it will end.
    Tick begin_pass(EventQueue& events, Tick start, const RendererPass& pass);
    Tick busy_until() const { return busy_until_; }
    // Answers a GP's fetch of `units` units (words of the PPs' data) that arrived at `arrival`: fetches
    // and passes are served one at a time in the order they come. Returns when the reply is ready to leave.
    // A batch of fetches in one request pays the setup once: `with_setup` false for all but its first.
    Tick serve_fetch(Tick arrival, std::uint64_t units, bool with_setup = true);
    // Reads `words` 32-bit words the PPs computed (a bit plane, say) out onto the ring port for a
    // message of the renderer's own, through the same port and at the same cost as a fetch's reply.
    // Starts at `ready` or when the renderer is next free; returns when the message can leave.
    Tick read_out(Tick ready, std::uint64_t words);
    // Screen work (a renderer owning a region of the picture): `runs` runs of one PP program over the
    // whole array, one per primitive (every PP evaluates the primitive at once), after the controller
    // has written `write_words` words from the ring into the PPs. Starts at `ready` or when the
    // renderer is next free; returns when it ends.
    Tick draw(Tick ready, const std::string& program, const PpProgramCost& cost, std::uint64_t runs,
              std::uint64_t write_words, int local_memory_bits_used);
    // Bits of each PP's backing store holding data, as the kernel that placed it reports.
    void set_backing_store_bits_used(std::uint64_t bits) { backing_store_bits_used_ = bits; }
    std::uint64_t backing_store_bits_used() const { return backing_store_bits_used_; }
    // Records passes and requests as slices on this renderer's track (nullptr: no trace).
    void set_trace(TraceRecorder* trace);

    Counter& busy_ps;
    Counter& fetches;
    Counter& units_sent;
    Counter& fetch_busy_ps;
    Counter& fetch_wait_ps;
    Counter& primitives_drawn;
    Counter& draw_busy_ps;
    Counter& words_written;
    Counter& read_outs;
    Counter& words_read_out;

private:
    void handle_event(Tick now, std::uint64_t payload) override;

    std::size_t index_;
    ClockDomain clock_;
    std::uint64_t columns_;
    std::uint64_t rows_;
    std::uint64_t local_memory_bits_;
    std::uint64_t backing_store_bits_;
    PpCostModel cost_model_;
    std::uint64_t fetch_setup_cycles_;
    double fetch_cycles_per_unit_;
    std::uint64_t write_setup_cycles_;
    double write_cycles_per_word_;
    std::unique_ptr<PpArray> array_;
    TraceRecorder* trace_ = nullptr;
    int trace_track_ = 0;
    Tick busy_until_ = 0;
    std::uint64_t backing_store_bits_used_ = 0;
    std::uint64_t local_memory_bits_peak_ = 0;
    std::uint64_t last_slot_cycles_ = 0;

    Counter& passes_;
    Counter& slots_;
    Counter& busy_cycles_;
    Counter& alu_cycles_;
    Counter& controller_cycles_;
    Counter& backing_store_stall_cycles_;
    Counter& backing_store_blocks_;
    Counter& instructions_;
    Counter& pp_operations_;
    Counter& enabled_pp_operations_;
};

}  // namespace pp5
