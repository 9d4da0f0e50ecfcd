// The ray caster's timing layer on hand-made work: latency hiding by switching ray contexts, as the
// model predicts, and cache reuse between rays.

#include "kernels/levoy/pp_shading.h"
#include "kernels/levoy/ray_cast_timing.h"
#include "kernels/levoy/voxel_blocks.h"
#include "sim/machine/machine.h"

#include <gtest/gtest.h>

#include <string>

namespace pp5 {
namespace {

// One GP, one renderer, and a ring whose hops are slow: a fixed request latency that costs the ring
// and the renderer almost no occupancy, so only the GP's context switching can hide it.
MachineConfig latency_machine(int contexts) {
    std::vector<const ParamGroup*> groups = Machine::param_groups();
    MachineConfig config(groups);
    for (const std::string o : {"gp.count=1", "renderer.count=1", "renderer.pp_columns=16", "renderer.pp_rows=16",
                                "ring.hop_latency_cycles=1000", "renderer.request_setup_cycles=0", "renderer.request_cycles_per_voxel=0"})
        config.apply_override(o);
    config.apply_override("gp.ray_contexts=" + std::to_string(contexts));
    return config;
}

constexpr int kRays = 64;
constexpr int kTouchesPerRay = 4;
constexpr std::uint32_t kSamplesPerTouch = 20;

// Every ray needs kTouchesPerRay blocks no other ray needs, kSamplesPerTouch samples before each.
RayCastJob distinct_blocks_job(bool shared = false) {
    RayCastJob job;
    CastBatch batch;
    for (int r = 0; r < kRays; ++r) {
        RayWork ray;
        ray.pixel = static_cast<std::uint32_t>(r);
        ray.first_touch = static_cast<std::uint32_t>(batch.touches.size());
        ray.touch_count = kTouchesPerRay;
        ray.samples = kTouchesPerRay * kSamplesPerTouch;
        for (int t = 0; t < kTouchesPerRay; ++t) {
            const auto block = static_cast<std::uint32_t>(shared ? t : r * kTouchesPerRay + t);
            batch.touches.push_back(BlockTouch{block, kSamplesPerTouch, 0});
        }
        batch.rays.push_back(ray);
        batch.colors.emplace_back(0.0f);
    }
    job.passes.push_back(std::move(batch));
    job.tasks.push_back(TileTask{0, 0, 0, kRays, 0, 0, kRays});
    job.tiles = 1;
    return job;
}

struct Timed {
    RayCastReport report;
    Tick compute_per_touch;
    Tick round_trip;
};

Timed run(int contexts, bool shared = false) {
    const MachineConfig config = latency_machine(contexts);
    Machine machine(config);
    const VoxelPlacement placement(PlacementPolicy::Bricks, glm::ivec3(9), PpArrayShape{1, 16, 16, 4096}, 64);
    VoxelBlocks blocks(placement, 1, 32);
    const RayCastJob job = distinct_blocks_job(shared);
    Timed out{time_ray_casting(machine, blocks, job, RayCastTimingOptions{}, 0), 0, 0};
    const GpCostModel& c = machine.gps().front()->costs();
    out.compute_per_touch = kSamplesPerTouch * c.per_sample() + c.cache_lookup + c.message_send + c.message_receive;
    // Two hops out, three back round the four stations (host, gp, renderer, frame buffer), 1000
    // cycles each, plus the two messages' words.
    const RingNetwork& ring = machine.ring();
    const std::uint64_t words = ring.message_words(64) + ring.message_words(8 * 32);
    out.round_trip = ring.clock().cycles_to_ticks(4 * 1000 + words);
    return out;
}

double seconds_of(const Timed& t) { return ticks_to_seconds(t.report.end - t.report.start); }

TEST(RayCastTiming, OneContextPaysEveryRequestLatencyInFull) {
    const Timed t = run(1);
    const double touches = kRays * kTouchesPerRay;
    const double predicted = touches * ticks_to_seconds(t.compute_per_touch + t.round_trip);
    EXPECT_NEAR(seconds_of(t), predicted, 0.05 * predicted);
    EXPECT_EQ(t.report.cache_misses, static_cast<std::uint64_t>(touches));
    EXPECT_EQ(t.report.requests, static_cast<std::uint64_t>(touches));
    EXPECT_GT(t.report.gp_wait, t.report.gp_busy);  // latency dominates
}

TEST(RayCastTiming, MoreContextsHideMoreLatencyAsTheModelPredicts) {
    double previous = 1e30;
    for (const int contexts : {1, 2, 3, 4, 8, 16}) {
        const Timed t = run(contexts);
        const double touches = kRays * kTouchesPerRay;
        const double compute = ticks_to_seconds(t.compute_per_touch);
        const double latency = ticks_to_seconds(t.round_trip);
        // c rays in flight overlap their waits: a touch costs (compute + latency) / c, but never less
        // than its compute (plus a switch, which the bound leaves out).
        const double predicted = touches * std::max(compute, (compute + latency) / contexts);
        const double measured = seconds_of(t);
        EXPECT_NEAR(measured, predicted, 0.15 * predicted) << contexts << " contexts";
        EXPECT_LE(measured, previous * 1.0001) << contexts << " contexts";
        previous = measured;
    }
}

TEST(RayCastTiming, BlocksFetchedOnceServeLaterRaysFromTheCache) {
    const Timed t = run(1, /*shared=*/true);
    EXPECT_EQ(t.report.cache_misses, static_cast<std::uint64_t>(kTouchesPerRay));
    EXPECT_EQ(t.report.cache_hits, static_cast<std::uint64_t>((kRays - 1) * kTouchesPerRay));
    // Only the first ray waits: the rest is compute, (72 + 200) / 72 times faster than fetching all.
    const Timed distinct = run(1);
    const double touches = kRays * kTouchesPerRay;
    const double predicted = touches * ticks_to_seconds(distinct.compute_per_touch) + kTouchesPerRay * ticks_to_seconds(distinct.round_trip);
    EXPECT_NEAR(seconds_of(t), predicted, 0.05 * predicted);
    EXPECT_LT(seconds_of(t), seconds_of(distinct) / 3);
}

TEST(RayCastTiming, ContextsWaitingForTheSameBlockShareOneRequest) {
    const Timed t = run(8, /*shared=*/true);
    EXPECT_EQ(t.report.requests, static_cast<std::uint64_t>(kTouchesPerRay));
    EXPECT_EQ(t.report.rays, static_cast<std::uint64_t>(kRays));
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

// A job of hand-made passes: each inner vector is one pass's rays, each ray the blocks it needs in
// turn (with `samples` samples before each) and `tail` samples after.
struct HandRay {
    std::vector<std::uint32_t> blocks;
    std::uint32_t samples = 1;
    std::uint32_t tail = 0;
};

RayCastJob hand_job(const std::vector<std::vector<HandRay>>& passes) {
    RayCastJob job;
    job.tiles = 1;
    for (std::size_t p = 0; p < passes.size(); ++p) {
        CastBatch batch;
        for (const HandRay& h : passes[p]) {
            RayWork ray;
            ray.first_touch = static_cast<std::uint32_t>(batch.touches.size());
            ray.touch_count = static_cast<std::uint32_t>(h.blocks.size());
            ray.tail_samples = h.tail;
            for (const std::uint32_t b : h.blocks) batch.touches.push_back(BlockTouch{b, h.samples, 0});
            batch.rays.push_back(ray);
            batch.colors.emplace_back(0.0f);
        }
        job.tasks.push_back(TileTask{static_cast<int>(p), 0, 0, static_cast<std::uint32_t>(passes[p].size()), 0, 0, 64});
        job.passes.push_back(std::move(batch));
    }
    return job;
}

RayCastReport run_hand(const RayCastJob& job, int contexts) {
    const MachineConfig config = latency_machine(contexts);
    Machine machine(config);
    const VoxelPlacement placement(PlacementPolicy::Bricks, glm::ivec3(9), PpArrayShape{1, 16, 16, 4096}, 64);
    VoxelBlocks blocks(placement, 1, 32);
    return time_ray_casting(machine, blocks, job, RayCastTimingOptions{}, 0);
}

TEST(RayCastTiming, APassWaitsForThePassBeforeIt) {
    // Pass 1's only ray needs nothing fetched, but its pixels were chosen from pass 0's colours.
    const RayCastReport r = run_hand(hand_job({{HandRay{{0}}}, {HandRay{{}, 1, 5}}}), 2);
    ASSERT_EQ(r.pass_end.size(), 2u);
    EXPECT_GT(r.pass_end[1], r.pass_end[0]);
}

TEST(RayCastTiming, RepliesAreTakenInAtTheNextSwitch) {
    // One ray needs four blocks in turn; 63 others only compute. With several contexts the GP takes
    // each reply in while the others run, so the slow ray's waits hide behind their work.
    std::vector<HandRay> rays{HandRay{{0, 1, 2, 3}}};
    for (int i = 0; i < 63; ++i) rays.push_back(HandRay{{}, 1, 200});
    const RayCastJob job = hand_job({rays});
    const RayCastReport one = run_hand(job, 1);
    const RayCastReport eight = run_hand(job, 8);
    EXPECT_GT(one.gp_wait, 0);
    EXPECT_LT(eight.gp_wait, one.gp_wait / 4) << "waits not hidden: " << eight.gp_wait << " ps";
    EXPECT_LT(eight.end, one.end);
}

}  // namespace
}  // namespace pp5
