// The browser tool's view without HTTP: each change is the next frame of one running session, so only
// what it invalidates is recomputed; a bad change is refused naming its field and leaves the view as
// it was; and the rate the page shows is the frame's simulated time.

#include "frontends/serve/interactive_view.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <map>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

Scenario small_scenario(bool region, const std::string& more_shading = "") {
    const fs::path file =
        fs::temp_directory_path() / ("pp5_view_test_" + std::to_string(getpid()) + (region ? "_region" : "") + ".toml");
    std::ofstream(file) << "[scenario]\nname = \"view-test\"\n[dataset]\nphantom = \"head\"\nsize = 32\n[image]\nwidth "
                           "= 48\nheight = 48\n"
                           "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 40.0, opacity = 0.0 }, "
                           "{ value = 120.0, opacity = 0.9 }]\n"
                           "[shading]\nlight_direction = [0.4, 1.0, 0.5]\nspecular = 0.0\n"
                        << more_shading << "[camera]\nazimuth = 30.0\nelevation = 10.0\n"
                        << (region ? "[region]\nshape = \"box\"\ncenter = [16.0, 10.0, 16.0]\nhalf_size = [6.0, 6.0, "
                                     "6.0]\nscale_inside = 0.0\n"
                                   : "")
                        << "[[frames]]\nlabel = \"first\"\n";
    Scenario s = load_scenario(file);
    fs::remove(file);
    return s;
}

const nlohmann::json& phase(const nlohmann::json& state, const std::string& name) {
    for (const auto& p : state["frame"]["phases"])
        if (p["name"] == name) return p;
    throw std::runtime_error("no phase " + name);
}

double control(const nlohmann::json& state, const std::string& key) {
    for (const auto& c : state["machine_parameters"])
        if (c["key"] == key) return c["value"].get<double>();
    throw std::runtime_error("no control " + key);
}

// The machine in the page: a change of timing alone (GP count, ring, caches) re-times the recorded
// frame at once, with the same picture; one that changes what is computed renders again.
TEST(InteractiveView, AMachineChangeOfTimingOnlyRetimesTheFrameAndAnotherRendersAgain) {
    InteractiveView view(small_scenario(false), load_run_config("pxpl5", {}));
    const nlohmann::json before = view.state();
    const std::string picture = view.frame_png();
    const double gps = control(before, "gp.count");
    ASSERT_GT(gps, 4);
    // The calibration in force is among the controls, and re-times like any timing parameter.
    EXPECT_EQ(control(before, "calibration.gp_flops_scale"), 1.0);
    view.apply({{"machine", {{"calibration.gp_flops_scale", 2.0}}}});
    EXPECT_EQ(view.state()["machine_change"]["kind"], "re-timed");
    EXPECT_GT(view.state()["frame"]["simulated_seconds"].get<double>(),
              before["frame"]["simulated_seconds"].get<double>());
    view.apply({{"machine", {{"calibration.gp_flops_scale", 1.0}}}});
    EXPECT_EQ(view.state()["frame"]["simulated_seconds"], before["frame"]["simulated_seconds"]);

    view.apply({{"machine", {{"gp.count", 4}}}});
    const nlohmann::json fewer = view.state();
    EXPECT_EQ(fewer["machine_change"]["kind"], "re-timed");
    EXPECT_EQ(fewer["machine_change"]["keys"], nlohmann::json::array({"gp.count"}));
    EXPECT_EQ(view.frame_png(), picture);
    EXPECT_EQ(fewer["frame"]["index"], before["frame"]["index"]);  // no new frame
    EXPECT_GT(fewer["frame"]["simulated_seconds"].get<double>(), before["frame"]["simulated_seconds"].get<double>());
    EXPECT_EQ(control(fewer, "gp.count"), 4);
    EXPECT_NE(fewer["machine_summary"].get<std::string>().find(": 4 GPs"), std::string::npos)
        << fewer["machine_summary"];
    // Back to the first machine: the session's own time, replayed from cold caches as it was.
    view.apply({{"machine", {{"gp.count", gps}}}});
    EXPECT_EQ(view.state()["frame"]["simulated_seconds"], before["frame"]["simulated_seconds"]);
    // The next frame is timed on the machine as changed.
    view.apply({{"machine", {{"gp.count", 4}}}});
    view.apply({{"camera", {{"azimuth", 60}}}});
    EXPECT_TRUE(view.state()["machine_change"].is_null());
    EXPECT_EQ(control(view.state(), "gp.count"), 4);

    // The renderer count changes where the volume lives: rendered again.
    view.apply({{"machine", {{"renderer.count", 8}}}});
    const nlohmann::json rerendered = view.state();
    EXPECT_EQ(rerendered["machine_change"]["kind"], "rendered again");
    EXPECT_EQ(control(rerendered, "renderer.count"), 8);
    EXPECT_EQ(control(rerendered, "gp.count"), 4);  // the timing change stays

    // Refused naming the field, and nothing changes.
    const auto version = view.version();
    for (const auto& [change, field] : std::vector<std::pair<nlohmann::json, std::string>>{
             {{{"machine", {{"gp.count", 0}}}}, "machine.gp.count"},
             {{{"machine", {{"gp.cuont", 4}}}}, "machine.gp.cuont"},
             {{{"machine", {{"gp.count", "many"}}}}, "machine.gp.count"},
             {{{"machine", {{"gp.count", nullptr}}}}, "machine.gp.count"},
             {{{"machine", 3}}, "machine"},
             {{{"machine", {{"gp.count", 8}}}, {"camera", {{"zoom", 2}}}}, "machine"}}) {
        try {
            view.apply(change);
            ADD_FAILURE() << change.dump() << " accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), field) << e.what();
        }
    }
    EXPECT_EQ(view.version(), version);
}

// Where the time went: a lane per GP, renderer and ring channel of the machine that timed the frame,
// whose busy time agrees with the utilisation the state reports (two books of the same quantity); the
// passes reach the frame buffer in order within the frame; both follow a re-time on fewer GPs, as does
// the tile map.
TEST(InteractiveView, TheTimelineAndTileMapShowTheMachineThatTimedTheFrame) {
    InteractiveView view(small_scenario(false), load_run_config("pxpl5", {}));
    const auto check = [&](std::size_t gps, std::string& tile_map) {
        const nlohmann::json state = view.state();
        const nlohmann::json t = view.timeline(200);
        EXPECT_EQ(t["version"], state["version"]);
        EXPECT_DOUBLE_EQ(t["seconds"].get<double>(), state["frame"]["simulated_seconds"].get<double>());
        std::map<std::string, std::size_t> lanes;
        std::map<std::string, double> busy;  // summed over lanes and bins, in bins
        for (const auto& lane : t["lanes"]) {
            ++lanes[lane["group"]];
            ASSERT_EQ(lane["busy"].size(), 200u);
            ASSERT_EQ(lane["what"].size(), 200u);
            for (std::size_t b = 0; b < 200; ++b) {
                const double f = lane["busy"][b].get<double>();
                EXPECT_GE(f, 0.0);
                EXPECT_LE(f, 1.0);
                EXPECT_EQ(f > 0.0, lane["what"][b].get<int>() >= 0);
                if (f > 0.0) {
                    EXPECT_NE(t["activities"][lane["what"][b].get<std::size_t>()], "waiting");
                }
                busy[lane["group"]] += f;
            }
        }
        EXPECT_EQ(lanes["GPs"], gps);
        EXPECT_EQ(lanes["renderers"], static_cast<std::size_t>(control(state, "renderer.count")));
        EXPECT_GE(lanes["ring"], 1u);
        EXPECT_EQ(t["slices_dropped"], 0);
        // The lanes' busy time over count x frame is the utilisation the frame reports (to the
        // rounding of each bin's share to two decimals).
        EXPECT_NEAR(busy["GPs"] / (200.0 * static_cast<double>(gps)),
                    state["frame"]["utilisation"]["gps"].get<double>(), 0.01);
        EXPECT_NEAR(busy["ring"] / (200.0 * static_cast<double>(lanes["ring"])),
                    state["frame"]["utilisation"]["ring"].get<double>(), 0.01);
        // Each pass reaches the frame buffer after the one before, within the frame.
        const auto& ready = state["frame"]["passes_ready_seconds"];
        EXPECT_EQ(ready.size(), state["frame"]["passes"].get<std::size_t>());
        for (std::size_t p = 0; p < ready.size(); ++p) {
            EXPECT_GT(ready[p].get<double>(), p == 0 ? 0.0 : ready[p - 1].get<double>());
            EXPECT_LE(ready[p].get<double>(), t["seconds"].get<double>() * (1 + 1e-12));
        }
        EXPECT_TRUE(state["frame"]["tile_map"].get<bool>());
        const auto png = view.tile_map_png();
        ASSERT_TRUE(png.has_value());
        EXPECT_EQ(png->substr(1, 3), "PNG");
        tile_map = *png;
    };
    const std::size_t gps = static_cast<std::size_t>(control(view.state(), "gp.count"));
    ASSERT_GT(view.state()["frame"]["passes"].get<std::size_t>(), 1u);
    std::string many, three;
    check(gps, many);
    view.apply({{"machine", {{"gp.count", 3}}}});
    ASSERT_EQ(view.state()["machine_change"]["kind"], "re-timed");
    check(3, three);
    EXPECT_NE(three, many);  // the tiles are cast by other GPs
}

// The frame is shown before its oracle: the PSNR is pending until asked for, and then is what a
// session comparing every frame as it renders gives, however many frames went by unasked.
TEST(InteractiveView, TheReferenceIsRenderedWhenAskedForAndAgreesWithAComparingSession) {
    const Scenario scenario = small_scenario(true);
    InteractiveView every(scenario, load_run_config("pxpl5", {})), last(scenario, load_run_config("pxpl5", {}));
    EXPECT_TRUE(every.state()["frame"]["psnr_pending"].get<bool>());
    EXPECT_TRUE(every.state()["frame"]["psnr_db"].is_null());
    const nlohmann::json first = every.reference_fidelity();
    EXPECT_EQ(first["version"], every.state()["version"]);
    EXPECT_FALSE(every.state()["frame"]["psnr_pending"].get<bool>());
    EXPECT_EQ(every.state()["frame"]["psnr_db"], first["fidelity"]["psnr_db"]);

    RenderSession comparing(scenario, load_run_config("pxpl5", {}));
    const SessionFrame frame = comparing.render(scenario.frames.front());
    EXPECT_EQ(first["fidelity"], frame.record["fidelity"]);

    // A light move, a region move and a change of light again, the second view asking only at the end.
    for (const nlohmann::json& change : {nlohmann::json{{"light", {{"direction", {-0.6, 1.0, 0.3}}}}},
                                         nlohmann::json{{"region", {{"center", {14.0, 12.0, 16.0}}}}},
                                         nlohmann::json{{"light", {{"direction", {0.2, 1.0, -0.3}}}}}}) {
        every.apply(change);
        last.apply(change);
        EXPECT_TRUE(every.state()["frame"]["psnr_pending"].get<bool>());
        (void)every.reference_fidelity();
    }
    EXPECT_EQ(last.frame_png(), every.frame_png());
    EXPECT_EQ(last.reference_fidelity()["fidelity"], every.reference_fidelity()["fidelity"]);
    // A re-time keeps the picture, and so its distance from the reference.
    last.apply({{"machine", {{"gp.count", 4}}}});
    EXPECT_FALSE(last.state()["frame"]["psnr_pending"].get<bool>());
    EXPECT_EQ(last.state()["frame"]["psnr_db"], every.state()["frame"]["psnr_db"]);
}

// The page's compare mode: every kernel that runs on the machine renders the view as it stands, on
// the machine frames are timed on; Levoy's row is the view's own frame (a first frame either way).
TEST(InteractiveView, ComparingKernelsRendersTheViewAsItStandsWithEach) {
    InteractiveView view(small_scenario(false), load_run_config("pxpl5", {}));
    view.apply({{"machine", {{"gp.count", 4}}}});
    const nlohmann::json state = view.state();
    const nlohmann::json report = view.compare_kernels();
    EXPECT_EQ(report["version"], state["version"]);
    EXPECT_EQ(report["frames"], 1);
    std::size_t machine_kernels = 0;
    for (const Kernel* k : kernels()) machine_kernels += k->runs_on_machine() ? 1 : 0;
    ASSERT_EQ(report["kernels"].size(), machine_kernels);
    std::size_t rendered = 0;
    for (const auto& row : report["kernels"]) {
        const std::string kernel = row["kernel"];
        if (row.contains("refusal")) {
            EXPECT_FALSE(view.comparison_png(kernel).has_value());
            continue;
        }
        ++rendered;
        EXPECT_EQ(view.comparison_png(kernel).value().substr(1, 3), "PNG");
        if (kernel == "levoy") {
            EXPECT_EQ(row["frame_seconds"][0].get<double>(), state["frame"]["simulated_seconds"].get<double>());
        }
    }
    EXPECT_GE(rendered, 2u);
    EXPECT_FALSE(view.comparison_png("no-such-kernel").has_value());
    EXPECT_EQ(view.state()["version"], state["version"]);  // the view itself is unchanged
}

TEST(InteractiveView, ALightMoveReshadesAndCastsButKeepsTheClassificationAndPyramid) {
    InteractiveView view(small_scenario(false), load_run_config("pxpl5", {}));
    const std::string first = view.frame_png();
    EXPECT_TRUE(phase(view.state(), "pyramid")["ran"].get<bool>());
    view.apply({{"light", {{"direction", {-0.6, 1.0, 0.3}}}}});
    const nlohmann::json s = view.state();
    EXPECT_EQ(s["frame"]["index"], 1);
    EXPECT_TRUE(s["frame"]["changed"]["lighting"].get<bool>());
    EXPECT_FALSE(s["frame"]["changed"]["camera"].get<bool>());
    EXPECT_TRUE(phase(s, "shading")["ran"].get<bool>());
    EXPECT_TRUE(phase(s, "ray_casting")["ran"].get<bool>());
    EXPECT_FALSE(phase(s, "classification")["ran"].get<bool>());
    EXPECT_FALSE(phase(s, "pyramid")["ran"].get<bool>());
    EXPECT_NE(view.frame_png(), first);
    // The rate shown is the frame's simulated time, as stats.json records it.
    const double seconds = s["frame"]["simulated_seconds"].get<double>();
    EXPECT_DOUBLE_EQ(seconds, s["frame"]["record"]["simulated_seconds"].get<double>());
    EXPECT_DOUBLE_EQ(s["frame"]["frames_per_second"].get<double>(), 1.0 / seconds);
    for (const char* kind : {"gps", "renderers", "ring"}) {
        EXPECT_GT(s["frame"]["utilisation"][kind].get<double>(), 0.0) << kind;
        EXPECT_LE(s["frame"]["utilisation"][kind].get<double>(), 1.0) << kind;
    }
}

// Levoy's two bats: the page's light control moves the key light, the scenario's stationary lights
// stay, and their sum, stored by the first frame, is not recomputed.
TEST(InteractiveView, ALightMoveKeepsTheStationaryLightsAndTheirStoredSum) {
    InteractiveView view(
        small_scenario(false, "stationary_lights = [{ direction = [-1.0, 0.2, 0.3], intensity = 0.6 }]\n"),
        load_run_config("pxpl5", {}));
    EXPECT_TRUE(phase(view.state(), "stationary_lights")["ran"].get<bool>());
    const std::string first = view.frame_png();
    view.apply({{"light", {{"direction", {-0.6, 1.0, 0.3}}}}});
    const nlohmann::json s = view.state();
    EXPECT_TRUE(phase(s, "shading")["ran"].get<bool>());
    EXPECT_FALSE(phase(s, "stationary_lights")["ran"].get<bool>());
    EXPECT_NE(view.frame_png(), first);
    // Without them the same move gives another picture: they are still lighting it.
    InteractiveView unlit(small_scenario(false), load_run_config("pxpl5", {}));
    unlit.apply({{"light", {{"direction", {-0.6, 1.0, 0.3}}}}});
    EXPECT_NE(unlit.frame_png(), view.frame_png());
    const std::string unlit_picture = unlit.frame_png();

    // Stationary lights given by a change light the view as the scenario's own do, and go again.
    const nlohmann::json bat = {{"direction", {-1.0, 0.2, 0.3}}, {"intensity", 0.6}};
    unlit.apply({{"light", {{"stationary", {bat}}}}});
    EXPECT_EQ(unlit.frame_png(), view.frame_png());
    EXPECT_EQ(unlit.state()["light"]["stationary"].size(), 1u);
    EXPECT_FLOAT_EQ(unlit.state()["light"]["stationary"][0]["intensity"].get<float>(), 0.6f);
    unlit.apply({{"light", {{"stationary", nlohmann::json::array()}}}});
    EXPECT_EQ(unlit.frame_png(), unlit_picture);
    for (const auto& [stationary, field] : std::vector<std::pair<nlohmann::json, std::string>>{
             {nlohmann::json::array({bat, bat, bat, bat, bat, bat, bat, bat, bat}), "light.stationary"},
             {{{{"direction", {1, 0, 0}}, {"intensity", 11}}}, "light.stationary[0].intensity"},
             {{{{"direction", {0, 0, 0}}}}, "light.stationary[0].direction"},
             {{{{"intensity", 1}}}, "light.stationary[0].direction"},
             {{{{"direction", {1, 0, 0}}, {"colour", 1}}}, "light.stationary[0].colour"},
             {"left", "light.stationary"}}) {
        try {
            unlit.apply({{"light", {{"stationary", stationary}}}});
            ADD_FAILURE() << stationary.dump() << " accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), field) << e.what();
        }
    }
}

TEST(InteractiveView, AnOrbitCastsAgainWithoutReshadingAndAChangeOfNothingRendersNothing) {
    InteractiveView view(small_scenario(false), load_run_config("pxpl5", {}));
    view.apply({{"camera", {{"azimuth", 45.0}}}});
    const nlohmann::json s = view.state();
    EXPECT_FALSE(phase(s, "shading")["ran"].get<bool>());
    EXPECT_TRUE(phase(s, "ray_casting")["ran"].get<bool>());
    EXPECT_FLOAT_EQ(s["camera"]["azimuth"].get<float>(), 45.0f);
    const std::size_t version = view.version();
    view.apply({{"camera", {{"azimuth", 45.0}}}});
    EXPECT_EQ(view.version(), version);
}

TEST(InteractiveView, MovingTheRegionReclassifiesAndChangesThePicture) {
    InteractiveView view(small_scenario(true), load_run_config("pxpl5", {}));
    const std::string before = view.frame_png();
    view.apply({{"region", {{"center", {16.0, 14.0, 16.0}}}}});
    const nlohmann::json s = view.state();
    EXPECT_TRUE(s["frame"]["changed"]["region"].get<bool>());
    EXPECT_TRUE(phase(s, "region_of_interest")["ran"].get<bool>());
    EXPECT_FALSE(phase(s, "shading")["ran"].get<bool>());
    EXPECT_FLOAT_EQ(s["region"]["center"][1].get<float>(), 14.0f);
    EXPECT_NE(view.frame_png(), before);
    // A capping region's colours follow it: moving it reshades as well.
    view.apply({{"region", {{"cap", true}, {"transition", 2.0}}}});
    EXPECT_TRUE(view.state()["region"]["cap"].get<bool>());
    EXPECT_TRUE(phase(view.state(), "shading")["ran"].get<bool>());
    view.apply({{"region", {{"center", {16.0, 12.0, 16.0}}}}});
    EXPECT_TRUE(phase(view.state(), "shading")["ran"].get<bool>());
    view.apply({{"region", nullptr}});
    EXPECT_TRUE(view.state()["region"].is_null());
}

TEST(InteractiveView, BadChangesNameTheirFieldAndChangeNothing) {
    InteractiveView view(small_scenario(true), load_run_config("pxpl5", {}));
    const nlohmann::json before = view.state();
    const std::vector<std::pair<nlohmann::json, std::string>> bad = {
        {{{"camera", {{"azimuth", "east"}}}}, "camera.azimuth"},
        {{{"camera", {{"elevation", 95.0}}}}, "camera.elevation"},
        {{{"camera", {{"roll", 1.0}}}}, "camera.roll"},
        {{{"light", {{"direction", {0.0, 0.0, 0.0}}}}}, "light.direction"},
        {{{"light", {{"direction", {1.0, 2.0}}}}}, "light.direction"},
        {{{"region", {{"half_size", {0.0, 1.0, 1.0}}}}}, "region.half_size[0]"},
        {{{"region", {{"scale_inside", 17.0}}}}, "region.scale_inside"},
        {{{"region", {{"shape", "torus"}}}}, "region.shape"},
        {{{"region", {{"cap", "yes"}}}}, "region.cap"},
        {{{"region", {{"shape", "ellipsoid"}, {"cap", true}}}}, "region.cap"},
        {{{"kernel", "no-such-kernel"}}, "kernel"},
        {{{"kernel", "yuan"}}, "kernel"},  // Yuan's kernel has no volume-of-interest tool
        {{{"zoom", 2.0}}, "zoom"},
        {nlohmann::json::array(), ""},
        // A valid camera with a bad light: nothing of the change is applied.
        {{{"camera", {{"azimuth", 90.0}}}, {"light", {{"headlight", 3}}}}, "light.headlight"},
    };
    for (const auto& [change, field] : bad) {
        try {
            view.apply(change);
            ADD_FAILURE() << "accepted " << change.dump();
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), "request");
            EXPECT_EQ(e.field(), field) << change.dump() << ": " << e.what();
        }
    }
    const nlohmann::json after = view.state();
    EXPECT_EQ(after["version"], before["version"]);
    EXPECT_EQ(after["camera"], before["camera"]);
    EXPECT_EQ(after["kernel"], "levoy");
}

TEST(InteractiveView, ChoosingAnotherKernelRendersTheSameViewWithIt) {
    InteractiveView view(small_scenario(false), load_run_config("pxpl5", {}));
    std::vector<std::string> kernels;
    const nlohmann::json state = view.state();
    for (const auto& k : state["kernels"]) kernels.push_back(k["name"].get<std::string>());
    EXPECT_NE(std::find(kernels.begin(), kernels.end(), "yuan"), kernels.end());
    view.apply({{"camera", {{"azimuth", 50.0}}}, {"kernel", "yuan"}});
    const nlohmann::json s = view.state();
    EXPECT_EQ(s["kernel"], "yuan");
    EXPECT_FLOAT_EQ(s["camera"]["azimuth"].get<float>(), 50.0f);
    EXPECT_GT(s["frame"]["simulated_seconds"].get<double>(), 0.0);
}

}  // namespace
}  // namespace pp5
