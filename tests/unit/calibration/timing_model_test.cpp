// Re-timing recorded work must give exactly what rendering on the re-timed machine gives; machines that
// would compute something else are refused; the uniprocessor's scan-conversion grows with area.

#include "calibration/timing_model.h"
#include "calibration_support.h"
#include "frontends/run_config.h"
#include "kernels/levoy/sequential_timing.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <gtest/gtest.h>

namespace pp5 {
namespace {

TEST(TimingModel, RetimingEqualsRenderingOnTheRetimedMachine) {
    const test::CalibrationFiles files = test::write_calibration_files("retime");
    const Scenario scenario = load_scenario(files.scenario);
    const MachineConfig recorded_on = load_run_config(files.machine.string(), {});
    const RecordedScenario recording(scenario, recorded_on, 3);

    // Every kind of timing parameter changes: GP count, costs, ring, cache, renderer clock, scales.
    const MachineConfig other = load_run_config(files.machine.string(),
                                                {"gp.count=3", "gp_cost.sample_step_flops=9", "ring.clock_mhz=10", "gp.cache_bits=200000",
                                                 "renderer.clock_mhz=33", "calibration.gp_cycles_scale=1.7", "calibration.pp_cycles_scale=0.6"});
    const std::vector<FrameTimes> retimed = recording.time_on(other);
    ASSERT_EQ(retimed.size(), 3u);

    Machine machine(other);
    const Volume volume = load_dataset(scenario);
    LevoyRenderer workstation(machine, volume, LevoySettings::from(other), levoy_image_settings(scenario.image));
    for (std::size_t i = 0; i < 3; ++i) {
        const LevoyFrameReport report = workstation.render(levoy_frame_inputs(scenario.frames[i], volume));
        EXPECT_EQ(retimed[i].crude_seconds, ticks_to_seconds(report.passes.front().end_ps)) << "frame " << i;
        EXPECT_EQ(retimed[i].refined_seconds, ticks_to_seconds(report.duration_ps())) << "frame " << i;
        EXPECT_EQ(retimed[i].pp_seconds, ticks_to_seconds(report.pixel_processors.duration_ps())) << "frame " << i;
    }
    // And the changes did change the times, or the comparison would prove little.
    EXPECT_NE(retimed[0].refined_seconds, recording.time_on(recorded_on)[0].refined_seconds);
}

TEST(TimingModel, AMachineThatComputesSomethingElseIsRefused) {
    const test::CalibrationFiles files = test::write_calibration_files("refuse");
    const MachineConfig recorded_on = load_run_config(files.machine.string(), {});
    const RecordedScenario recording(load_scenario(files.scenario), recorded_on, 1);
    try {
        (void)recording.time_on(load_run_config(files.machine.string(), {"levoy.refinement_threshold=0.3"}));
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "levoy.refinement_threshold");
        EXPECT_NE(std::string(e.what()).find("re-times recorded work"), std::string::npos) << e.what();
    }
}

TEST(SequentialTiming, ScanConversionGrowsInProportionToArea) {
    // Levoy: on a sequential machine the cost of scan-converting a polygon is proportional to its area.
    const MachineConfig sun = load_run_config("sun4-280", {});
    const GpCostModel costs = GpCostModel::from(sun);
    const auto seconds_for = [&](double area) {
        LevoyFrameWork work;
        work.jitter_samples = 16;
        work.scan_converted = true;
        work.polygons = 1;
        work.polygon_passes.push_back(PolygonWork{{}, 0, area, 4});
        return ticks_to_seconds(time_levoy_frame_sequentially(costs, work).scan_conversion);
    };
    const double small = seconds_for(1000.0);
    EXPECT_GT(small, 0.0);
    EXPECT_NEAR(seconds_for(2000.0) / small, 2.0, 1e-9);
    EXPECT_NEAR(seconds_for(8000.0) / small, 8.0, 1e-9);
    // The closed form: 2 voxels per unit area, J x (edges + 1) tests and a matte each.
    EXPECT_NEAR(small, 1000.0 * kSequentialVoxelsPerUnitArea * (16.0 * 5.0 * 2.0 + 12.0) / 1.1e6, small * 1e-6);
}

TEST(SequentialTiming, RayCastingIsTheSumOfItsOperations) {
    // One pass of two rays and a tile's refinement work, against the sum written out by hand.
    const MachineConfig sun = load_run_config("sun4-280", {});
    const GpCostModel c = GpCostModel::from(sun);
    LevoyFrameWork work;
    CastBatch batch;
    RayWork a;
    a.samples = 10;
    a.pyramid_steps = 4;
    RayWork b;
    b.samples = 3;
    b.pyramid_steps = 1;
    batch.rays = {a, b};
    work.ray_cast.passes.push_back(batch);
    TileTask task;
    task.squares_tested = 5;
    task.pixels_filled = 7;
    work.ray_cast.tasks.push_back(task);
    const SequentialFrameTiming t = time_levoy_frame_sequentially(c, work);
    const Tick expected = 2 * c.ray_setup + 13 * c.per_sample() + 5 * c.pyramid_step + 5 * c.refinement_test + 7 * c.pixel_fill;
    EXPECT_EQ(t.crude_ps(), expected);
    EXPECT_EQ(t.refined_ps(), expected);
}

}  // namespace
}  // namespace pp5
