// The lecture pictures: the passes strip keeps every pass's pixels, and the GP tile map colours each
// tile by the GP the timing engine says ran it, on a real frame of a small scenario.

#include "frontends/lecture_pictures.h"
#include "frontends/render_session.h"
#include "kernels/registry/run_config.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <set>

namespace pp5 {
namespace {

TEST(LecturePictures, TheStripHoldsEveryPassSideBySide) {
    Image a(3, 2), b(3, 2);
    std::fill(a.pixels.begin(), a.pixels.end(), glm::vec4(0.2f, 0.0f, 0.0f, 1.0f));
    std::fill(b.pixels.begin(), b.pixels.end(), glm::vec4(0.0f, 0.7f, 0.0f, 1.0f));
    const Image strip = passes_strip({a, b});
    EXPECT_EQ(strip.height, 2);
    EXPECT_EQ(strip.width, 3 + 4 + 3);
    EXPECT_EQ(strip.at(1, 1), a.at(1, 1));
    EXPECT_EQ(strip.at(8, 0), b.at(1, 0));
    EXPECT_THROW(passes_strip({}), std::invalid_argument);
}

TEST(LecturePictures, TheTileMapColoursEachTileByTheGpThatRanIt) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("pp5_pictures_" + std::to_string(getpid()) + ".toml");
    std::ofstream(file) << "[scenario]\nname = \"pictures\"\n[dataset]\nphantom = \"sphere\"\nsize = "
                           "24\n[image]\nwidth = 64\nheight = 64\n"
                           "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 50.0, opacity = 0.0 }, "
                           "{ value = 150.0, opacity = 0.8 }]\n";
    const Scenario scenario = load_scenario(file);
    std::filesystem::remove(file);
    RenderSession session(scenario, load_run_config("pxpl5", {"gp.count=4"}));
    const SessionFrame frame = session.render(scenario.frames.front());
    const Image& picture = *frame.find(FrameImage::Kind::Frame);
    const auto map = gp_tile_map(frame.recorded->work, frame.timing, 4, picture);
    ASSERT_TRUE(map.has_value());
    EXPECT_EQ(map->width, 64);
    // Every GP ran some tiles, and each shows in its own colour (tile interiors, away from the edges).
    std::set<std::tuple<float, float, float>> hues;
    const PhaseTiming* casting = frame.timing.phase("ray_casting");
    ASSERT_NE(casting, nullptr);
    std::set<std::uint32_t> gps(casting->task_gp.begin(), casting->task_gp.end());
    EXPECT_EQ(gps, (std::set<std::uint32_t>{0, 1, 2, 3}));
    for (int ty = 0; ty < 64; ty += 16)
        for (int tx = 0; tx < 64; tx += 16) {
            const glm::vec4 p = map->at(tx + 1, ty + 1);
            const glm::vec4 q = picture.at(tx + 1, ty + 1);
            const float brightness = 0.3f * q.r + 0.59f * q.g + 0.11f * q.b;
            const float scale = 0.45f + 0.55f * std::clamp(brightness, 0.0f, 1.0f);
            hues.insert({std::round(p.r / scale * 100), std::round(p.g / scale * 100), std::round(p.b / scale * 100)});
        }
    EXPECT_GE(hues.size(), 2u);
    EXPECT_LE(hues.size(), 4u);
    // A phase that is not screen tiles has no map.
    EXPECT_FALSE(gp_tile_map(frame.recorded->work, frame.timing, 4, picture, "no_such_phase").has_value());
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

TEST(LecturePictures, UtilisationOverTimeIsBusyTimePerBinOverTheComponentCount) {
    TraceRecorder trace(0, 0, 0);  // keeps no events, only the busy spans
    trace.keep_busy_spans(true);
    const int gp0 = trace.track("GPs", "gp[0]"), gp1 = trace.track("GPs", "gp[1]"),
              ring = trace.track("ring", "channel[0]");
    trace.slice(gp0, "computing", 0, 100);   // the whole first half
    trace.slice(gp1, "computing", 50, 100);  // half of it
    trace.slice(gp1, "waiting", 100, 200);   // idle: not counted
    trace.slice(ring, "fetch_request", 150, 200);
    const PlotSpec spec = utilisation_over_time(trace, 0, 200, {{"GPs", 2}, {"ring", 1}, {"renderers", 4}}, 2);
    ASSERT_EQ(spec.series.size(), 2u);  // nothing recorded for the renderers
    const PlotSeries& gps = spec.series[0].title == "GPs" ? spec.series[0] : spec.series[1];
    const PlotSeries& channel = spec.series[0].title == "GPs" ? spec.series[1] : spec.series[0];
    EXPECT_DOUBLE_EQ(gps.y[0], (100.0 + 50.0) / (2 * 100.0));
    EXPECT_DOUBLE_EQ(gps.y[1], 0.0);
    EXPECT_DOUBLE_EQ(channel.y[0], 0.0);
    EXPECT_DOUBLE_EQ(channel.y[1], 0.5);
    EXPECT_EQ(trace.events(), 0u);
}

}  // namespace
}  // namespace pp5
