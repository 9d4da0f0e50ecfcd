#include "frontends/render_session.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

Scenario phantom_scenario(const std::string& kernel) {
    const fs::path file =
        fs::temp_directory_path() / ("pp5_session_test_" + std::to_string(getpid()) + "_" + kernel + ".toml");
    std::ofstream(file) << "[scenario]\nname = \"session-test\"\nkernel = \"" << kernel
                        << "\"\n[dataset]\nphantom = \"head\"\nsize = 32\n"
                        << "[image]\nwidth = 48\nheight = 40\n"
                        << "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 40.0, opacity = 0.0 }, "
                           "{ value = 120.0, opacity = 0.9 }]\n";
    Scenario s = load_scenario(file);
    fs::remove(file);
    return s;
}

// The up-front estimate of a frame's pictures covers what a session really holds for the frame (its
// images, and the reference picture where there is one), without overstating it by more than the
// comparison's buffers and a pass the refinement may not need.
TEST(RenderSession, TheUpFrontPictureEstimateCoversWhatAFrameHolds) {
    for (const std::string kernel : {"levoy", "reference", "wilson"}) {
        const Scenario scenario = phantom_scenario(kernel);
        const MachineConfig config = load_run_config("pxpl5", {});
        RenderSession session(scenario, config);
        const SessionFrame frame = session.render(scenario.frames.front());
        double held = 0;
        for (const FrameImage& image : frame.images) held += 16.0 * static_cast<double>(image.image.pixels.size());
        if (session.kernel().runs_on_machine()) held += 16.0 * 48 * 40;  // the reference picture it was compared with
        const double estimate = picture_bytes_per_frame(session.kernel(), scenario, config);
        EXPECT_GE(estimate, held) << kernel;
        EXPECT_LE(estimate, 1.6 * held) << kernel;
    }
}

}  // namespace
}  // namespace pp5
