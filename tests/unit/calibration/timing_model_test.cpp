// Re-timing recorded work must give exactly what rendering on the re-timed machine gives; machines that
// would compute something else are refused.

#include "calibration/timing_model.h"
#include "calibration_support.h"
#include "kernels/levoy/levoy_kernel.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"
#include "tests/support/param_values.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>
#include <vector>

namespace pp5 {
namespace {

using test::other_values;

// What a recorded frame computed: its pictures and the shape of its work, as one comparable string.
std::string computed(const RecordedScenario& recording) {
    const RecordedFrame& frame = recording.frames().front();
    std::string digest;
    for (const Image* image : {&frame.crude_image, &frame.refined_image})
        for (const glm::vec4& p : image->pixels) digest += fmt::format("{} {} {} {};", p.r, p.g, p.b, p.a);
    for (const Phase& phase : frame.frame->work.phases) {
        digest += fmt::format(" {}", phase.name);
        if (const auto* pp = std::get_if<PpPhase>(&phase.work)) {
            for (const PpPhase::Pass& pass : pp->passes)
                for (const PpRunCounts& c : pass.work.counts) digest += fmt::format(" {}", c.enabled_pp_operations);
        } else if (const auto* gp = std::get_if<GpPhase>(&phase.work)) {
            digest += fmt::format(" {} {} {} {} {}", gp->steps.size(), gp->items.size(), gp->tasks.size(), gp->groups,
                                  gp->batches.size());
        }
    }
    return digest;
}

// Every parameter that declares it only changes timing (so calibration, sweeps and the browser tool
// re-time recorded work instead of rendering again) leaves the pictures and the recorded work of a
// frame as they were, at another value it accepts.
TEST(TimingModel, ParametersDeclaredTimingOnlyChangeNothingAFrameComputes) {
    const test::CalibrationFiles files = test::write_calibration_files("timing_only");
    const Scenario scenario = load_scenario(files.scenario);
    const MachineConfig base = load_run_config(files.machine.string(), {});
    const std::string expected = computed(RecordedScenario(scenario, base, 1));
    std::size_t checked = 0;
    for (const ParamGroup* group : base.groups()) {
        for (const ParamSpec& spec : group->specs()) {
            if (!spec.timing_only) continue;
            const std::string key = group->prefix() + "." + spec.name;
            EXPECT_TRUE(is_timing_parameter(key)) << key;
            bool recorded = false;
            for (const std::string& value : other_values(spec)) {
                try {
                    const RecordedScenario other(scenario, load_run_config(files.machine.string(), {key + "=" + value}),
                                                 1);
                    EXPECT_EQ(computed(other), expected) << key << " = " << value;
                    recorded = true;
                    break;
                } catch (const InputError&) {
                    // The machine cannot hold the work at that value (a cache past the GP's memory): try another.
                }
            }
            EXPECT_TRUE(recorded) << key << ": no other value could be tried";
            ++checked;
        }
    }
    EXPECT_GT(checked, 90u);
    EXPECT_FALSE(is_timing_parameter("renderer.pp_columns"));
    EXPECT_FALSE(is_timing_parameter("levoy.jitter_samples"));
    EXPECT_FALSE(is_timing_parameter("no.such_key"));
}

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
