#include "sim/components/renderer.h"

#include <algorithm>
#include <cmath>

namespace pp5 {

const ParamGroup& Renderer::params() {
    static const ParamGroup group = [] {
        ParamGroup g("renderer", "Renderers: SIMD arrays of bit-serial pixel processors");
        g.integer("count", 16, "count", 1, 1024, "Number of renderers", Provenance::Paper,
                  "Levoy 1989: 1/4 million PPs in 16 renderers")
            .integer("pp_columns", 128, "count", 1, 4096, "Pixel processors per row of the array", Provenance::Hardware,
                     "Fuchs et al. 1989: 128x128 PPs per renderer")
            .integer("pp_rows", 128, "count", 1, 4096, "Pixel processors per column of the array", Provenance::Hardware,
                     "Fuchs et al. 1989: 128x128 PPs per renderer")
            .integer("local_memory_bits", 208, "bits", 8, 1 << 20, "On-chip memory per pixel processor",
                     Provenance::Hardware, "Fuchs et al. 1989: 208 bits per PP")
            .integer("backing_store_bits", 4096, "bits", 0, 1 << 24, "Off-chip backing store per pixel processor",
                     Provenance::Paper, "Levoy 1989 and Fuchs et al. 1989: 4K bits per PP")
            .integer("backing_store_block_bits", 32, "bits", 1, 4096,
                     "Size of one backing-store transfer between local memory and the backing store",
                     Provenance::Default,
                     "machine.md's summary of Fuchs et al. 1989 (not among the papers here to check): moved in 32-bit "
                     "blocks")
            .real("clock_mhz", 40.0, "MHz", 1, 1000, "Pixel-processor clock", Provenance::Hardware,
                  "Fuchs et al. 1989: chips designed for 40 MHz")
            .timing_only()
            .integer("fetch_setup_cycles", 64, "cycles", 0, 1 << 24,
                     "Controller cycles to decode a GP's fetch request and set up the read-out", Provenance::Default,
                     "not published: a few dozen controller instructions")
            .plausible_factor(0.5, 2, "'a few dozen' instructions: from one to a hundred and more")
            .timing_only()
            .real("fetch_cycles_per_unit", 4.0, "cycles", 0, 1 << 20,
                  "Cycles to read one unit of a fetched block (a 32-bit word: one of Levoy's shaded voxels) out of the "
                  "PPs onto the ring port",
                  Provenance::Default, "not published: a 32-bit word through the renderer's port in a few cycles")
            .plausible(1, 8, "a word a cycle at best; 8 if the port is a byte wide")
            .timing_only()
            .integer("write_setup_cycles", 64, "cycles", 0, 1 << 24,
                     "Controller cycles to set up writing a block of words that arrived over the ring into the PPs (a "
                     "pixel block)",
                     Provenance::Default, "not published: taken as the fetch set-up, the same port the other way")
            .plausible_factor(0.5, 2, "as renderer.fetch_setup_cycles")
            .timing_only()
            .real("write_cycles_per_word", 4.0, "cycles", 0, 1 << 20,
                  "Cycles to write one 32-bit word that arrived over the ring into the PP it is for",
                  Provenance::Default, "not published: taken as the fetch rate, the same port the other way")
            .plausible(1, 8, "as renderer.fetch_cycles_per_unit")
            .timing_only();
        return g;
    }();
    return group;
}

Renderer::Renderer(std::size_t index, const MachineConfig& config)
    : Component(indexed("renderer", index), nullptr),
      busy_ps(stats().counter("busy_time", "ps", "Simulated time busy: PP passes, fetches and drawing")),
      fetches(stats().counter("fetches", "count", "GPs' fetch requests answered")),
      units_sent(stats().counter("units_sent", "count", "Units (words) read out in answer to fetches")),
      fetch_busy_ps(stats().counter("fetch_busy_time", "ps", "Simulated time spent answering fetches")),
      fetch_wait_ps(stats().counter("fetch_wait_time", "ps", "Time fetch requests waited for the renderer to be free")),
      primitives_drawn(stats().counter("primitives_drawn", "count",
                                       "Primitives drawn over the renderer's screen region (program runs)")),
      draw_busy_ps(
          stats().counter("draw_busy_time", "ps", "Simulated time spent drawing primitives over the screen region")),
      words_written(stats().counter("words_written", "count",
                                    "Words that arrived over the ring written into the PPs (pixel blocks)")),
      read_outs(stats().counter("read_outs", "count",
                                "Messages of the renderer's own read out of the PPs (the pyramid's bit planes)")),
      words_read_out(
          stats().counter("words_read_out", "count", "Words read out of the PPs for the renderer's own messages")),
      index_(index),
      clock_(ClockDomain::from_megahertz(name() + ".clock", config.real("renderer.clock_mhz"))),
      columns_(static_cast<std::uint64_t>(config.integer("renderer.pp_columns"))),
      rows_(static_cast<std::uint64_t>(config.integer("renderer.pp_rows"))),
      local_memory_bits_(static_cast<std::uint64_t>(config.integer("renderer.local_memory_bits"))),
      backing_store_bits_(static_cast<std::uint64_t>(config.integer("renderer.backing_store_bits"))),
      cost_model_(config),
      fetch_setup_cycles_(static_cast<std::uint64_t>(config.integer("renderer.fetch_setup_cycles"))),
      fetch_cycles_per_unit_(config.real("renderer.fetch_cycles_per_unit")),
      write_setup_cycles_(static_cast<std::uint64_t>(config.integer("renderer.write_setup_cycles"))),
      write_cycles_per_word_(config.real("renderer.write_cycles_per_word")),
      passes_(
          stats().counter("passes", "count", "PP program runs over data slots (a record in every PP's backing store)")),
      slots_(stats().counter("slots", "count", "Data slots processed, summed over passes")),
      busy_cycles_(stats().counter("busy_cycles", "cycles", "PP clock cycles spent in passes and drawing")),
      alu_cycles_(stats().counter("alu_cycles", "cycles", "Of busy_cycles, the PPs computing")),
      controller_cycles_(
          stats().counter("controller_cycles", "cycles", "Of busy_cycles, the controller issuing instructions")),
      backing_store_stall_cycles_(
          stats().counter("backing_store_stall_cycles", "cycles",
                          "Of busy_cycles, waiting for backing-store transfers not hidden by computation")),
      backing_store_blocks_(
          stats().counter("backing_store_blocks", "count", "Blocks moved between local memory and backing store")),
      instructions_(stats().counter("instructions", "count", "PP instructions broadcast")),
      pp_operations_(stats().counter("pp_operations", "count", "Instructions times PPs")),
      enabled_pp_operations_(stats().counter("enabled_pp_operations", "count", "Of pp_operations, on enabled PPs")) {
    stats().formula("pixel_processors", "count", "Pixel processors in this renderer's array",
                    [this] { return static_cast<double>(pixel_processors()); });
    stats().formula("memory_bits", "bits", "Local memory plus backing store over all of this renderer's PPs", [this] {
        return static_cast<double>(pixel_processors() * (local_memory_bits_ + backing_store_bits_));
    });
    stats().formula("enabled_fraction", "ratio", "Share of PP operations done on enabled PPs", [this] {
        const auto all = pp_operations_.value();
        return all == 0 ? 0.0 : static_cast<double>(enabled_pp_operations_.value()) / static_cast<double>(all);
    });
    stats().formula("local_memory_bits_used", "bits", "Peak local memory per PP used by any program run here",
                    [this] { return static_cast<double>(local_memory_bits_peak_); });
    stats().formula("backing_store_bits_used", "bits", "Backing store per PP holding placed data",
                    [this] { return static_cast<double>(backing_store_bits_used_); });
    stats().formula("slot_cycles", "cycles", "Cycles of one data slot (computation and issue) in the last pass",
                    [this] { return static_cast<double>(last_slot_cycles_); });
}

PpArray& Renderer::array() {
    if (!array_) {
        array_ = std::make_unique<PpArray>(columns(), rows(), static_cast<int>(local_memory_bits_),
                                           static_cast<int>(backing_store_bits_));
    }
    return *array_;
}

Tick Renderer::begin_pass(EventQueue& events, Tick start, const RendererPass& pass) {
    const Tick begin = clock_.next_edge(std::max(start, busy_until_));
    const PpPassCycles cycles = cost_model_.pass(pass.cost, pass.slots);
    const Tick duration = clock_.cycles_to_ticks(cycles.total);
    busy_until_ = begin + duration;

    ++passes_;
    slots_ += pass.slots;
    busy_cycles_ += cycles.total;
    alu_cycles_ += cycles.alu;
    controller_cycles_ += cycles.controller;
    backing_store_stall_cycles_ += cycles.backing_store_stall;
    backing_store_blocks_ += (pass.cost.load_blocks + pass.cost.store_blocks) * pass.slots;
    instructions_ += pass.counts.instructions;
    pp_operations_ += pass.counts.pp_operations;
    enabled_pp_operations_ += pass.counts.enabled_pp_operations;
    busy_ps += static_cast<std::uint64_t>(duration);
    local_memory_bits_peak_ =
        std::max(local_memory_bits_peak_, static_cast<std::uint64_t>(pass.local_memory_bits_used));
    last_slot_cycles_ = pass.cost.compute_cycles();

    if (trace_ != nullptr) trace_->slice(trace_track_, pass.program, begin, busy_until_);
    events.schedule(busy_until_, *this);
    return busy_until_;
}

Tick Renderer::serve_fetch(Tick arrival, std::uint64_t units, bool with_setup) {
    const Tick begin = clock_.next_edge(std::max(arrival, busy_until_));
    const auto cycles = (with_setup ? fetch_setup_cycles_ : 0) +
                        static_cast<std::uint64_t>(std::ceil(fetch_cycles_per_unit_ * static_cast<double>(units)));
    const Tick duration = clock_.cycles_to_ticks(cycles);
    busy_until_ = begin + duration;
    ++fetches;
    units_sent += units;
    fetch_busy_ps += static_cast<std::uint64_t>(duration);
    fetch_wait_ps += static_cast<std::uint64_t>(begin - arrival);
    busy_ps += static_cast<std::uint64_t>(duration);
    if (trace_ != nullptr) trace_->slice(trace_track_, "answering a fetch", begin, busy_until_);
    return busy_until_;
}

Tick Renderer::read_out(Tick ready, std::uint64_t words) {
    const Tick begin = clock_.next_edge(std::max(ready, busy_until_));
    const auto cycles = fetch_setup_cycles_ +
                        static_cast<std::uint64_t>(std::ceil(fetch_cycles_per_unit_ * static_cast<double>(words)));
    busy_until_ = begin + clock_.cycles_to_ticks(cycles);
    ++read_outs;
    words_read_out += words;
    busy_ps += static_cast<std::uint64_t>(busy_until_ - begin);
    if (trace_ != nullptr) trace_->slice(trace_track_, "reading out", begin, busy_until_);
    return busy_until_;
}

Tick Renderer::draw(Tick ready, const std::string& program, const PpProgramCost& cost, std::uint64_t runs,
                    std::uint64_t write_words, int local_memory_bits_used) {
    const Tick begin = clock_.next_edge(std::max(ready, busy_until_));
    const PpPassCycles cycles = cost_model_.pass(cost, runs);
    const std::uint64_t write_cycles =
        write_words == 0
            ? 0
            : write_setup_cycles_ +
                  static_cast<std::uint64_t>(std::ceil(write_cycles_per_word_ * static_cast<double>(write_words)));
    const Tick duration = clock_.cycles_to_ticks(cycles.total + write_cycles);
    busy_until_ = begin + duration;
    primitives_drawn += runs;
    words_written += write_words;
    busy_cycles_ += cycles.total + write_cycles;
    alu_cycles_ += cycles.alu;
    controller_cycles_ += cycles.controller;
    backing_store_stall_cycles_ += cycles.backing_store_stall;
    draw_busy_ps += static_cast<std::uint64_t>(duration);
    busy_ps += static_cast<std::uint64_t>(duration);
    local_memory_bits_peak_ = std::max(local_memory_bits_peak_, static_cast<std::uint64_t>(local_memory_bits_used));
    if (trace_ != nullptr) trace_->slice(trace_track_, program, begin, busy_until_);
    return busy_until_;
}

void Renderer::set_trace(TraceRecorder* trace) {
    trace_ = trace;
    if (trace_ != nullptr) trace_track_ = trace_->track("renderers", name());
}

void Renderer::handle_event(Tick, std::uint64_t) {
    // The pass is over; the renderer takes new work from busy_until_ on (fetches queue behind passes,
    // and the timing engine starts the next phase itself).
}

}  // namespace pp5
