// Re-timing recorded work must give exactly what rendering on the re-timed machine gives; machines that
// would compute something else are refused.

#include "calibration/timing_model.h"
#include "calibration_support.h"
#include "kernels/levoy/levoy_kernel.h"
#include "kernels/registry/run_config.h"
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
    const MachineConfig other =
        load_run_config(files.machine.string(), {"gp.count=3", "gp_cost.levoy.sample_step_flops=9", "ring.clock_mhz=10",
                                                 "gp.cache_bits=200000", "renderer.clock_mhz=33",
                                                 "calibration.gp_cycles_scale=1.7", "calibration.pp_cycles_scale=0.6"});
    const std::vector<FrameTiming> retimed = recording.time_on(other);
    ASSERT_EQ(retimed.size(), 3u);

    Machine machine(other);
    const Volume volume = load_dataset(scenario);
    LevoyRenderer workstation(machine, volume, LevoySettings::from(other), levoy_image_settings(scenario.image));
    for (std::size_t i = 0; i < 3; ++i) {
        const LevoyFrameReport report = workstation.render(levoy_frame_inputs(scenario.frames[i], volume));
        EXPECT_EQ(recording.metric("crude_seconds", i, retimed[i]), ticks_to_seconds(report.passes.front().end_ps))
            << "frame " << i;
        EXPECT_EQ(recording.metric("refined_seconds", i, retimed[i]), ticks_to_seconds(report.duration_ps()))
            << "frame " << i;
        EXPECT_EQ(recording.metric("pp_seconds", i, retimed[i]),
                  ticks_to_seconds(report.pixel_processors.duration_ps()))
            << "frame " << i;
    }
    // And the changes did change the times, or the comparison would prove little.
    EXPECT_NE(retimed[0].duration_ps(), recording.time_on(recorded_on)[0].duration_ps());
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

}  // namespace
}  // namespace pp5
