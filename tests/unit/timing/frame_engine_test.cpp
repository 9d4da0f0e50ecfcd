// The timing engine on hand-made recorded work: latency hiding by switching contexts as the model
// predicts, cache reuse, groups waiting for the group before, replies taken in at the next switch, the
// frame buffer counting what arrives, the machine's limits refused up front, the watchdog, broadcast
// and PP phases, and the same work summed on one processor.

#include "sim/timing/frame_engine.h"
#include "sim/components/gp_cost_model.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"
#include "sim/timing/one_processor.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace pp5 {
namespace {

// A kernel of the test's own: one operation kind costed by a real machine parameter.
std::vector<GpOpKind> kinds() { return {{"test.sample", {"gp_cost.cache_lookup_cycles"}}}; }

// One GP, one renderer, and a ring whose hops are slow: a fixed fetch latency that costs the ring and
// the renderer almost no occupancy, so only the GP's context switching can hide it.
MachineConfig latency_machine(int contexts) {
    MachineConfig config(Machine::param_groups());
    for (const std::string o :
         {"gp.count=1", "renderer.count=1", "renderer.pp_columns=16", "renderer.pp_rows=16",
          "ring.hop_latency_cycles=1000", "renderer.fetch_setup_cycles=0", "renderer.fetch_cycles_per_unit=0"})
        config.apply_override(o);
    config.apply_override("gp.ray_contexts=" + std::to_string(contexts));
    return config;
}

// Blocks of 8 units of 32 bits, every one held by renderer 0.
std::shared_ptr<const BlockDirectory> directory(std::uint32_t blocks) {
    std::vector<std::uint32_t> first;
    std::vector<BlockPart> parts;
    for (std::uint32_t b = 0; b <= blocks; ++b) first.push_back(b);
    for (std::uint32_t b = 0; b < blocks; ++b) parts.push_back(BlockPart{0, 8});
    return std::make_shared<const BlockDirectory>(8 * 32, 32, first, parts);
}

// Items that each fetch the given blocks in turn, `samples` operations before each and `tail` after.
struct HandItem {
    std::vector<std::uint32_t> blocks;
    std::uint32_t samples = 1;
    std::uint32_t tail = 0;
};

FrameWork hand_frame(const std::vector<std::vector<HandItem>>& groups, std::uint32_t pixels = 64) {
    GpPhase phase;
    phase.blocks = directory(512);
    phase.groups = static_cast<std::uint32_t>(groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g) {
        GpTask task;
        task.group = static_cast<std::uint32_t>(g);
        task.first_item = static_cast<std::uint32_t>(phase.items.size());
        for (const HandItem& h : groups[g]) {
            GpItem item{static_cast<std::uint32_t>(phase.steps.size()), 0};
            for (const std::uint32_t b : h.blocks) {
                phase.ops.push_back(GpOp{0, h.samples});
                phase.steps.push_back(GpStep{static_cast<std::uint32_t>(phase.ops.size()) - 1, 1, b});
                ++item.step_count;
            }
            if (h.tail > 0) {
                phase.ops.push_back(GpOp{0, h.tail});
                phase.steps.push_back(GpStep{static_cast<std::uint32_t>(phase.ops.size()) - 1, 1, kNoFetch});
                ++item.step_count;
            }
            phase.items.push_back(item);
        }
        task.item_count = static_cast<std::uint32_t>(groups[g].size());
        task.pixels = pixels;
        phase.tasks.push_back(task);
    }
    FrameWork frame;
    frame.op_kinds = kinds();
    frame.phases.push_back(Phase{"gp work", std::move(phase)});
    return frame;
}

constexpr int kItems = 64;
constexpr int kFetchesPerItem = 4;
constexpr std::uint32_t kSamplesPerFetch = 20;

// Every item needs kFetchesPerItem blocks no other item needs (or, shared, the same ones).
FrameWork distinct_blocks(bool shared = false) {
    std::vector<HandItem> items;
    for (int r = 0; r < kItems; ++r) {
        HandItem h;
        h.samples = kSamplesPerFetch;
        for (int t = 0; t < kFetchesPerItem; ++t)
            h.blocks.push_back(static_cast<std::uint32_t>(shared ? t : r * kFetchesPerItem + t));
        items.push_back(h);
    }
    return hand_frame({items});
}

struct Timed {
    FrameTiming timing;
    GpPhaseCounts counts;
    Tick compute_per_fetch;  // a miss: the samples, the look-up, the request and the reply
    Tick messages;           // of that, the request and the reply
    Tick round_trip;
};

Timed run(int contexts, bool shared = false) {
    Machine machine(latency_machine(contexts));
    Timed out{time_frame(machine, distinct_blocks(shared)), {}, 0, 0, 0};
    out.counts = out.timing.phases.front().gp;
    const GpCostModel& c = machine.gps().front()->costs();
    const Tick sample = gp_op_costs(machine.config(), kinds()).front();
    out.messages = c.message_send + c.message_receive;
    out.compute_per_fetch = kSamplesPerFetch * sample + c.cache_lookup + out.messages;
    // Two hops out, three back round the four stations (host, gp, renderer, frame buffer), 1000
    // cycles each, plus the two messages' words.
    const RingNetwork& ring = machine.ring();
    const std::uint64_t words = ring.message_words(64) + ring.message_words(8 * 32);
    out.round_trip = ring.clock().cycles_to_ticks(4 * 1000 + words);
    return out;
}

double seconds_of(const Timed& t) { return ticks_to_seconds(t.timing.duration_ps()); }

TEST(FrameEngine, OneContextPaysEveryFetchLatencyInFull) {
    const Timed t = run(1);
    const double fetches = kItems * kFetchesPerItem;
    const double predicted = fetches * ticks_to_seconds(t.compute_per_fetch + t.round_trip);
    EXPECT_NEAR(seconds_of(t), predicted, 0.05 * predicted);
    EXPECT_EQ(t.counts.cache_misses, static_cast<std::uint64_t>(fetches));
    EXPECT_EQ(t.counts.fetch_requests, static_cast<std::uint64_t>(fetches));
    EXPECT_GT(t.counts.gp_wait, t.counts.gp_busy);  // latency dominates
}

TEST(FrameEngine, MoreContextsHideMoreLatencyAsTheModelPredicts) {
    double previous = 1e30;
    for (const int contexts : {1, 2, 3, 4, 8, 16}) {
        const Timed t = run(contexts);
        const double fetches = kItems * kFetchesPerItem;
        const double compute = ticks_to_seconds(t.compute_per_fetch);
        const double latency = ticks_to_seconds(t.round_trip);
        // c items in flight overlap their waits: a fetch costs (compute + latency) / c, but never less
        // than its compute (plus a switch, which the bound leaves out).
        const double predicted = fetches * std::max(compute, (compute + latency) / contexts);
        const double measured = seconds_of(t);
        EXPECT_NEAR(measured, predicted, 0.15 * predicted) << contexts << " contexts";
        EXPECT_LE(measured, previous * 1.0001) << contexts << " contexts";
        previous = measured;
    }
}

TEST(FrameEngine, BlocksFetchedOnceServeLaterItemsFromTheCache) {
    const Timed t = run(1, /*shared=*/true);
    EXPECT_EQ(t.counts.cache_misses, static_cast<std::uint64_t>(kFetchesPerItem));
    EXPECT_EQ(t.counts.cache_hits, static_cast<std::uint64_t>((kItems - 1) * kFetchesPerItem));
    // Only the first item waits and sends; the rest is compute.
    const Timed distinct = run(1);
    const double fetches = kItems * kFetchesPerItem;
    const double predicted = fetches * ticks_to_seconds(distinct.compute_per_fetch - distinct.messages) +
                             kFetchesPerItem * ticks_to_seconds(distinct.messages + distinct.round_trip);
    EXPECT_NEAR(seconds_of(t), predicted, 0.05 * predicted);
    EXPECT_LT(seconds_of(t), seconds_of(distinct) / 3);
}

TEST(FrameEngine, ContextsWaitingForTheSameBlockShareOneRequest) {
    const Timed t = run(8, /*shared=*/true);
    EXPECT_EQ(t.counts.fetch_requests, static_cast<std::uint64_t>(kFetchesPerItem));
    EXPECT_EQ(t.counts.items, static_cast<std::uint64_t>(kItems));
}

FrameTiming run_hand(const FrameWork& frame, int contexts) {
    Machine machine(latency_machine(contexts));
    return time_frame(machine, frame);
}

TEST(FrameEngine, AGroupWaitsForTheGroupBeforeIt) {
    // Group 1's only item needs nothing fetched, but its work was chosen from group 0's results.
    const FrameTiming t = run_hand(hand_frame({{HandItem{{0}}}, {HandItem{{}, 1, 5}}}), 2);
    const PhaseTiming& p = t.phases.front();
    ASSERT_EQ(p.group_end_ps.size(), 2u);
    EXPECT_GT(p.group_end_ps[1], p.group_end_ps[0]);
}

TEST(FrameEngine, RepliesAreTakenInAtTheNextSwitch) {
    // One item needs four blocks in turn; 63 others only compute. With several contexts the GP takes
    // each reply in while the others run, so the slow item's waits hide behind their work.
    std::vector<HandItem> items{HandItem{{0, 1, 2, 3}}};
    for (int i = 0; i < 63; ++i) items.push_back(HandItem{{}, 1, 200});
    const FrameWork frame = hand_frame({items});
    const FrameTiming one = run_hand(frame, 1);
    const FrameTiming eight = run_hand(frame, 8);
    EXPECT_GT(one.phases.front().gp.gp_wait, 0);
    EXPECT_LT(eight.phases.front().gp.gp_wait, one.phases.front().gp.gp_wait / 4);
    EXPECT_LT(eight.end_ps, one.end_ps);
}

TEST(FrameEngine, TheFrameBufferCountsThePixelsThatArrive) {
    Machine machine(latency_machine(2));
    const FrameTiming t =
        time_frame(machine, hand_frame({{HandItem{{0}}}, {HandItem{{1}}}, {HandItem{{}, 1, 3}}}, 100));
    EXPECT_EQ(t.phases.front().gp.pixels_sent, 300u);
    EXPECT_EQ(machine.frame_buffer().pixels_written.value(), 300u);
    const nlohmann::json stats = machine.statistics();
    EXPECT_EQ(stats["ring"]["messages"]["value"]["pixel_block"].get<std::uint64_t>(), 3u);
    // 24-bit pixels by default: 100 of them are 75 words of 32 bits, plus the header.
    const std::uint64_t bytes = stats["ring"]["bytes"]["value"]["pixel_block"].get<std::uint64_t>();
    EXPECT_EQ(bytes, 3u * machine.ring().message_words(100 * 24) * 4);
}

TEST(FrameEngine, FrameBufferBitsPerPixelSizeThePixelMessages) {
    MachineConfig config = latency_machine(2);
    config.apply_override("frame_buffer.bits_per_pixel=32");
    Machine machine(config);
    (void)time_frame(machine, hand_frame({{HandItem{{}, 1, 3}}}, 100));
    EXPECT_EQ(machine.statistics()["ring"]["bytes"]["value"]["pixel_block"].get<std::uint64_t>(),
              machine.ring().message_words(3200) * 4);
}

TEST(FrameEngine, APictureLargerThanTheFrameBufferIsRefusedNamingTheKey) {
    MachineConfig config = latency_machine(1);
    config.apply_override("frame_buffer.width=64");
    Machine machine(config);
    FrameWork frame = hand_frame({{HandItem{{0}}}});
    frame.image_width = 128;
    frame.image_height = 32;
    try {
        (void)time_frame(machine, frame);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "frame_buffer.width");
    }
    EXPECT_EQ(machine.events().now(), 0);  // refused before anything ran
}

TEST(FrameEngine, AGpWhoseMemoryCannotHoldItsCacheAndDataIsRefused) {
    MachineConfig config = latency_machine(1);
    config.apply_override("gp.cache_bits=65536");    // 8 KiB
    config.apply_override("gp.memory_bytes=12288");  // 12 KiB
    Machine machine(config);
    FrameWork frame = hand_frame({{HandItem{{0}}}});
    frame.gp_resident_bits = 4096 * 8;  // 4 KiB: fits exactly
    EXPECT_NO_THROW((void)time_frame(machine, frame));
    frame.gp_resident_bits += 8;
    Machine again(config);
    try {
        (void)time_frame(again, frame);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "gp.memory_bytes");
        EXPECT_NE(std::string(e.what()).find("12289"), std::string::npos) << e.what();
    }
}

TEST(FrameEngine, WatchdogNamesThePhaseTheGpAndTheBlock) {
    MachineConfig config = latency_machine(1);
    config.apply_override("renderer.fetch_setup_cycles=10000000");  // a quarter second per fetch
    Machine machine(config);
    EngineOptions options;
    options.watchdog_limit = kTicksPerSecond / 1000;
    try {
        (void)time_frame(machine, hand_frame({{HandItem{{7}}}}), options);
        FAIL() << "expected the watchdog to fire";
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("watchdog"), std::string::npos) << what;
        EXPECT_NE(what.find("gp work"), std::string::npos) << what;
        EXPECT_NE(what.find("gp[0]"), std::string::npos) << what;
        EXPECT_NE(what.find("block 7"), std::string::npos) << what;
    }
    EXPECT_TRUE(machine.events().empty());
}

TEST(FrameEngine, ABroadcastPhaseStreamsEveryMessageThenEveryGpComputes) {
    MachineConfig config = latency_machine(1);
    config.apply_override("gp.count=3");
    config.apply_override("renderer.count=2");
    Machine machine(config);
    FrameWork frame;
    frame.op_kinds = kinds();
    BroadcastPhase broadcast{{3, 2}, 256, {GpOp{0, 1000}}};
    frame.phases.push_back(Phase{"share", broadcast});
    const FrameTiming t = time_frame(machine, frame);
    const PhaseTiming& p = t.phases.front();
    const Tick compute = 1000 * gp_op_costs(machine.config(), kinds()).front();
    const GpCostModel& c = machine.gps().front()->costs();
    const Tick receive =
        5 * (c.message_receive + static_cast<Tick>(machine.ring().message_words(256)) * c.receive_per_word);
    EXPECT_GE(p.duration_ps(), compute + receive);
    EXPECT_EQ(machine.statistics()["ring"]["messages"]["value"]["broadcast"].get<std::uint64_t>(), 5u);
    for (const auto& gp : machine.gps()) {
        EXPECT_EQ(gp->operations("test.sample").value(), 1000u);
        EXPECT_EQ(gp->busy_ps.value(), static_cast<std::uint64_t>(compute + receive));
    }
}

TEST(FrameEngine, PhasesRunOneAfterAnotherInOneEventLoop) {
    Machine machine(latency_machine(2));
    FrameWork frame = hand_frame({{HandItem{{0}}}});
    frame.phases.insert(frame.phases.begin(), Phase{"share", BroadcastPhase{{4}, 256, {GpOp{0, 10}}}});
    const FrameTiming t = time_frame(machine, frame);
    ASSERT_EQ(t.phases.size(), 2u);
    EXPECT_EQ(t.phases[0].start_ps, t.start_ps);
    EXPECT_EQ(t.phases[1].start_ps, t.phases[0].end_ps);
    EXPECT_EQ(t.end_ps, t.phases[1].end_ps);
    EXPECT_EQ(t.phase("share"), &t.phases[0]);
    EXPECT_EQ(t.phase("nothing"), nullptr);
}

TEST(FrameEngine, APhaseThatSendsNoPixelsEndsWhenItsGpsFinish) {
    Machine machine(latency_machine(2));
    const FrameTiming t = time_frame(machine, hand_frame({{HandItem{{0}}, HandItem{{}, 1, 40}}}, /*pixels=*/0));
    const PhaseTiming& p = t.phases.front();
    EXPECT_GT(p.duration_ps(), 0);
    EXPECT_EQ(p.end_ps, machine.events().now());
    ASSERT_EQ(p.group_end_ps.size(), 1u);
    EXPECT_EQ(p.group_end_ps[0], p.start_ps);  // no pixels arrived for it
    EXPECT_EQ(machine.frame_buffer().pixels_written.value(), 0u);
}

TEST(FrameEngine, InconsistentRecordedWorkIsRefusedBeforeItRuns) {
    Machine machine(latency_machine(1));
    FrameWork no_directory = hand_frame({{HandItem{{0}}}});
    std::get<GpPhase>(no_directory.phases.front().work).blocks.reset();
    EXPECT_THROW((void)time_frame(machine, no_directory), std::logic_error);
    FrameWork unknown_block = hand_frame({{HandItem{{100000}}}});
    EXPECT_THROW((void)time_frame(machine, unknown_block), std::logic_error);
    FrameWork undeclared_kind = hand_frame({{HandItem{{0}}}});
    std::get<GpPhase>(undeclared_kind.phases.front().work).ops.front().kind = 7;
    EXPECT_THROW((void)time_frame(machine, undeclared_kind), std::logic_error);
    EXPECT_TRUE(machine.events().empty());
    EXPECT_EQ(machine.events().now(), 0);
}

TEST(FrameEngine, ACacheLargerThanTheGpsMemoryIsRefusedNamingTheKey) {
    MachineConfig config = latency_machine(1);
    config.apply_override("gp.cache_bits=1048576");  // 128 KiB
    config.apply_override("gp.memory_bytes=65536");  // 64 KiB
    Machine machine(config);
    try {
        (void)time_frame(machine, hand_frame({{HandItem{{0}}}}));
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "gp.memory_bytes");
        EXPECT_NE(std::string(e.what()).find("131072 byte cache"), std::string::npos) << e.what();
    }
    // Asked for directly (as a kernel sizing its caches at start does), the cache names its own key.
    Machine again(config);
    try {
        (void)again.gps().front()->cache(256);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "gp.cache_bits");
    }
}

TEST(FrameEngine, ACacheTooBigToSimulateIsRefusedSayingWhatItWouldNeed) {
    MachineConfig config = latency_machine(1);
    config.apply_override("gp.cache_bits=1099511627776");  // 2^40 bits
    config.apply_override("gp.memory_bytes=1099511627776");
    Machine machine(config);
    try {
        (void)machine.gps().front()->cache(32);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "gp.cache_bits");
        // 2^35 blocks, each a tag and two use counts of 8 bytes on this computer.
        EXPECT_NE(std::string(e.what()).find("786432 MiB"), std::string::npos) << e.what();
    }
}

TEST(RecordedWork, LargeCountsSplitIntoSeveralOperations) {
    std::vector<GpOp> ops;
    append_ops(ops, 3, 0);
    EXPECT_TRUE(ops.empty());
    const std::uint64_t big = 10'000'000'000ull;
    append_ops(ops, 3, big);
    std::uint64_t total = 0;
    for (const GpOp& op : ops) {
        EXPECT_EQ(op.kind, 3u);
        total += op.count;
    }
    EXPECT_EQ(total, big);
    EXPECT_EQ(ops.size(), 3u);
}

TEST(OneProcessor, SumsEveryOperationOfEveryPhaseInGroupOrder) {
    MachineConfig config = latency_machine(1);
    FrameWork frame = hand_frame({{HandItem{{0, 1}, 5, 2}, HandItem{{}, 1, 3}}, {HandItem{{2}, 7, 0}}});
    frame.phases.insert(frame.phases.begin(), Phase{"share", BroadcastPhase{{4}, 256, {GpOp{0, 10}}}});
    const FrameTiming t = time_frame_on_one_processor(config, frame);
    const Tick op = gp_op_costs(config, kinds()).front();
    ASSERT_EQ(t.phases.size(), 2u);
    EXPECT_EQ(t.phases[0].duration_ps(), 10 * op);  // its computing only: no messages
    const PhaseTiming& gp = t.phases[1];
    ASSERT_EQ(gp.group_end_ps.size(), 2u);
    EXPECT_EQ(gp.group_end_ps[0], t.phases[0].end_ps + (5 + 5 + 2 + 3) * op);  // no fetch costs anything
    EXPECT_EQ(gp.group_end_ps[1], gp.group_end_ps[0] + 7 * op);
    EXPECT_EQ(t.end_ps, gp.group_end_ps[1]);
}

// Sort-middle screen work: two GPs each send one batch to one renderer, which must draw them in the
// order its region steps give (the second GP's first), whatever order they arrive in; then it reads
// its region out to the frame buffer, and the phase ends when that arrives.

PpProgram one_add_program(const std::string& name) {
    PpProgramBuilder b(name, 64);
    const PpField x = b.set_const("x", 3);
    b.add_const("y", x, 1);
    return b.finish();
}

FrameWork region_frame(std::uint32_t slow_ops) {
    GpPhase phase;
    phase.groups = 1;
    for (std::uint32_t t = 0; t < 2; ++t) {
        phase.ops.push_back(GpOp{0, t == 1 ? slow_ops : 1});
        GpTask task;
        task.key = t;  // GP t
        task.first_op = t;
        task.op_count = 1;
        task.first_batch = t;
        task.batch_count = 1;
        phase.tasks.push_back(task);
        phase.batches.push_back(PrimitiveBatch{0, 640});
    }
    phase.region_programs = {one_add_program("draw")};
    RegionWork region;
    region.steps = {RegionStep{1, 0, 5, 0}, RegionStep{0, 0, 7, 20}, RegionStep{kNoBatch, 0, 1, 0}};
    region.readout_pixels = 256;
    phase.regions = {region};
    FrameWork frame;
    frame.op_kinds = kinds();
    frame.phases.push_back(Phase{"screen", std::move(phase)});
    return frame;
}

TEST(FrameEngineRegions, RendererDrawsInItsOwnOrderThenReadsOut) {
    MachineConfig config = latency_machine(1);
    config.apply_override("gp.count=2");
    config.apply_override("ring.hop_latency_cycles=1");
    Machine machine(config);
    const FrameTiming timing = time_frame(machine, region_frame(100000));
    const PhaseTiming& screen = timing.phases.at(0);
    EXPECT_EQ(screen.gp.batches_sent, 2u);
    EXPECT_EQ(screen.gp.batch_bits, 1280u);
    EXPECT_EQ(screen.gp.primitives_drawn, 13u);
    Renderer& renderer = *machine.renderers().front();
    EXPECT_EQ(renderer.primitives_drawn.value(), 13u);
    EXPECT_EQ(renderer.words_written.value(), 20u);
    EXPECT_EQ(machine.frame_buffer().pixels_written.value(), 256u);
    EXPECT_EQ(static_cast<std::uint64_t>(screen.gp.renderer_drawing.at(0)), renderer.draw_busy_ps.value());
    // GP 1's batch (drawn first) leaves only after its 100000 slow operations; the renderer cannot draw
    // anything before that, so the phase lasts longer than those operations plus all the drawing.
    const Tick slow = 100000 * GpCostModel::cost_of(config, "gp_cost.cache_lookup_cycles");
    EXPECT_GT(screen.duration_ps(), slow + static_cast<Tick>(renderer.draw_busy_ps.value()));
    // With a fast GP 1 the same work ends sooner: the order waited for the slow batch, not the fast one.
    Machine quick(config);
    EXPECT_LT(time_frame(quick, region_frame(1)).phases.at(0).duration_ps(), slow);
}

TEST(FrameEngineRegions, RefusesAStepDrawingAnotherRenderersBatch) {
    MachineConfig config = latency_machine(1);
    config.apply_override("renderer.count=2");
    Machine machine(config);
    FrameWork frame = region_frame(1);
    GpPhase& phase = std::get<GpPhase>(frame.phases.front().work);
    phase.regions.push_back(RegionWork{});
    phase.batches[0].renderer = 1;
    EXPECT_THROW(time_frame(machine, frame), std::logic_error);
}

}  // namespace
}  // namespace pp5
