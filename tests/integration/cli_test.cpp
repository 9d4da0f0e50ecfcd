// Runs the pp5sim binary as a user would: good runs write whole outputs, bad input gets one clear
// error line, exit code 2 and no output, and the thread count changes nothing.

#include "tests/support/run_files.h"
#include "tests/support/source_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using pp5::test::read_file;
using pp5::test::without_host_fields;

struct RunResult {
    int exit_code;
    std::string output;  // stdout and stderr together
};

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("pp5_cli_test_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

RunResult run_command(const std::string& command_line, const fs::path& log_dir) {
    const fs::path log = log_dir / "log.txt";
    const std::string command = command_line + " > " + log.string() + " 2>&1";
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(log)};
}

RunResult run(const std::string& args, const fs::path& log_dir) {
    // Appended, not a chain of operator+ (GCC 12 warns falsely of a bounds error on the temporaries).
    std::string command = PP5SIM_BINARY;
    command += ' ';
    command += args;
    return run_command(command, log_dir);
}

// The same with PATH set to `path` alone (pp5sim itself is named by its full path).
RunResult run_with_path(const fs::path& path, const std::string& args, const fs::path& log_dir) {
    return run_command("env PATH=" + path.string() + " " + std::string(PP5SIM_BINARY) + " " + args, log_dir);
}

std::string scenario(const std::string& name) { return (pp5::test::source_dir() / "traces/scenarios" / name).string(); }

// Without a scenario, render runs the shipped default (the MR head, from the mricron-data package);
// a shipped scenario can also be named without its path.
TEST(Cli, RenderWithoutScenarioRunsTheDefaultAndNamesResolve) {
    const fs::path dir = scratch("default");
    const RunResult r = run("render --out " + (dir / "head").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto stats = nlohmann::json::parse(read_file(dir / "head/stats.json"));
    EXPECT_EQ(stats["summary"]["scenario"], "mr-head");
    EXPECT_EQ(stats["dataset"]["name"], "ch2");
    EXPECT_EQ(stats["summary"]["image_size"], nlohmann::json({512, 512}));
    EXPECT_TRUE(fs::exists(dir / "head/frame_0000.png"));

    const RunResult named = run("render sphere --out " + (dir / "sphere").string(), dir);
    ASSERT_EQ(named.exit_code, 0) << named.output;
    EXPECT_EQ(nlohmann::json::parse(read_file(dir / "sphere/stats.json"))["summary"]["scenario"], "sphere");

    const RunResult unknown = run("render no-such-scenario --out " + (dir / "none").string(), dir);
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_NE(unknown.output.find("no-such-scenario"), std::string::npos) << unknown.output;
    EXPECT_FALSE(fs::exists(dir / "none"));
}

TEST(Cli, RenderWritesImagesStatsAndConfig) {
    const fs::path dir = scratch("render");
    const RunResult r = run("render " + scenario("head-phantom.toml") + " --out " + (dir / "out").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(fs::exists(dir / "out" / ("frame_000" + std::to_string(i) + ".png")));
    const auto stats = nlohmann::json::parse(read_file(dir / "out/stats.json"));
    EXPECT_EQ(stats["summary"]["frames"], 4);
    EXPECT_EQ(stats["summary"]["simulated_seconds"].size(), 4u);
    EXPECT_TRUE(stats["summary"]["host_seconds"].is_number());
    EXPECT_GT(stats["frames"][0]["reference"]["samples"].get<long>(), 0);
    EXPECT_TRUE(stats["components"].contains("gp[31]"));
    EXPECT_TRUE(stats["components"].contains("renderer[15]"));
    EXPECT_TRUE(stats["components"].contains("ring.channel[7]"));
    // The renderers' passes: the first frame classifies and shades; a camera move or a light change
    // reshades only; a new classification reruns both (its colours are part of it).
    const auto& f = stats["frames"];
    EXPECT_EQ(stats["summary"]["kernel"], "levoy");
    EXPECT_TRUE(f[0]["renderers"]["classification"]["ran"].get<bool>());
    EXPECT_TRUE(f[0]["renderers"]["shading"]["ran"].get<bool>());
    EXPECT_FALSE(f[1]["renderers"]["classification"]["ran"].get<bool>());
    EXPECT_TRUE(f[1]["renderers"]["shading"]["ran"].get<bool>());
    EXPECT_FALSE(f[2]["renderers"]["classification"]["ran"].get<bool>());
    EXPECT_TRUE(f[3]["renderers"]["classification"]["ran"].get<bool>());
    for (int i = 0; i < 4; ++i) {
        EXPECT_GT(stats["summary"]["simulated_seconds"][i].get<double>(), 0.0);
        // The PPs' fixed-point colours and opacities give the reference's picture (perspective here).
        EXPECT_GE(f[i]["fidelity"]["psnr_db"].get<double>(), 35.0) << "frame " << i;
    }
    EXPECT_GT(stats["components"]["renderer[0]"]["busy_cycles"]["value"].get<double>(), 0.0);
    EXPECT_GT(stats["components"]["renderer[0]"]["slot_cycles"]["value"].get<double>(), 0.0);
    EXPECT_TRUE(stats.contains("placement"));
    // Frames record what changed, as the scenario says.
    EXPECT_EQ(stats["frames"][1]["changed"]["camera"], true);
    EXPECT_EQ(stats["frames"][1]["changed"]["lighting"], false);
    EXPECT_EQ(stats["frames"][3]["changed"]["classification"], true);
    const auto config = nlohmann::json::parse(read_file(dir / "out/config.json"));
    EXPECT_EQ(config["machine"]["name"], "pxpl5");
    EXPECT_EQ(config["parameters"]["gp.count"]["value"], 32);
    // No staging leftovers.
    for (const auto& e : fs::directory_iterator(dir / "out"))
        EXPECT_EQ(e.path().filename().string().rfind(".partial", 0), std::string::npos) << e.path();
}

// Skipping the host reference (for big volumes) changes nothing the machine does: the same pictures
// and simulated figures, only the reference's samples and the PSNR are gone.
TEST(Cli, WithoutTheReferenceTheMachinesResultsAreTheSame) {
    const fs::path dir = scratch("no_reference");
    const RunResult with = run("render sphere --out " + (dir / "with").string(), dir);
    ASSERT_EQ(with.exit_code, 0) << with.output;
    const RunResult without = run("render sphere --no-reference --out " + (dir / "without").string(), dir);
    ASSERT_EQ(without.exit_code, 0) << without.output;
    EXPECT_EQ(without.output.find("PSNR"), std::string::npos) << without.output;
    auto a = nlohmann::json::parse(read_file(dir / "with/stats.json"));
    auto b = nlohmann::json::parse(read_file(dir / "without/stats.json"));
    ASSERT_EQ(a["frames"].size(), b["frames"].size());
    for (std::size_t i = 0; i < a["frames"].size(); ++i) {
        auto& fa = a["frames"][i];
        auto& fb = b["frames"][i];
        EXPECT_TRUE(fa.contains("reference") && fa.contains("fidelity"));
        EXPECT_FALSE(fb.contains("reference") || fb.contains("fidelity"));
        fa.erase("reference");
        fa.erase("fidelity");
        fa.erase("host_seconds");
        fb.erase("host_seconds");
        EXPECT_EQ(fa, fb) << "frame " << i;
        const std::string image = fa["image"].get<std::string>();
        EXPECT_EQ(read_file(dir / "with" / image), read_file(dir / "without" / image)) << image;
    }
    EXPECT_EQ(a["components"], b["components"]);
}

// The GPs' side of each frame: refinement passes with their pictures and times, the cache, and a
// Chrome trace of the run with GP, renderer and ring tracks.
TEST(Cli, RenderReportsRefinementPassesAndWritesATrace) {
    const fs::path dir = scratch("trace");
    const fs::path trace = dir / "trace.json";
    const RunResult r = run(
        "render " + scenario("head-phantom.toml") + " --out " + (dir / "out").string() + " --trace " + trace.string(),
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto stats = nlohmann::json::parse(read_file(dir / "out/stats.json"));
    for (const auto& frame : stats["frames"]) {
        const auto& m = frame["machine"];
        ASSERT_GE(m["passes"].size(), 2u);
        EXPECT_LE(m["crude_seconds"].get<double>(), m["refined_seconds"].get<double>());
        double previous = 0.0;
        for (const auto& pass : m["passes"]) {
            EXPECT_TRUE(fs::exists(dir / "out" / pass["image"].get<std::string>())) << pass["image"];
            EXPECT_GE(pass["complete_seconds"].get<double>(), previous);
            previous = pass["complete_seconds"].get<double>();
        }
        EXPECT_GT(m["rays"].get<long>(), 0);
        EXPECT_GT(m["cache_hits"].get<long>() + m["cache_misses"].get<long>(), 0);
    }
    EXPECT_TRUE(stats["frames"][0]["machine"]["pyramid_rebuilt"].get<bool>());
    long fills = 0;
    for (int g = 0; g < 32; ++g)
        fills += stats["components"]["gp[" + std::to_string(g) + "].cache"]["fills"]["value"].get<long>();
    EXPECT_GT(fills, 0);
    const auto events = nlohmann::json::parse(read_file(trace))["traceEvents"];
    std::set<std::string> tracks;
    std::size_t slices = 0;
    for (const auto& e : events) {
        if (e["ph"] == "M" && e["name"] == "thread_name") tracks.insert(e["args"]["name"].get<std::string>());
        if (e["ph"] == "X") ++slices;
    }
    EXPECT_TRUE(tracks.count("gp[0]") && tracks.count("renderer[0]") && tracks.count("channel[0]")) << r.output;
    EXPECT_GT(slices, 100u);
}

TEST(Cli, BadTraceWindowIsRejectedBeforeAnyOutput) {
    const fs::path dir = scratch("bad_trace");
    const RunResult r = run("render " + scenario("sphere.toml") + " --out " + (dir / "out").string() + " --trace " +
                                (dir / "t.json").string() + " --trace-window 9:3",
                            dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--trace-window"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
    EXPECT_FALSE(fs::exists(dir / "t.json"));
}

TEST(Cli, SameResultsAtOneAndTwoThreads) {
    const fs::path dir = scratch("threads");
    for (const char* t : {"1", "2"}) {
        const RunResult r =
            run("render " + scenario("head-phantom.toml") + " --threads " + t + " --out " + (dir / t).string(), dir);
        ASSERT_EQ(r.exit_code, 0) << r.output;
    }
    for (int i = 0; i < 4; ++i) {
        const std::string name = "frame_000" + std::to_string(i) + ".png";
        EXPECT_EQ(read_file(dir / "1" / name), read_file(dir / "2" / name)) << name;
    }
    EXPECT_EQ(without_host_fields(nlohmann::json::parse(read_file(dir / "1/stats.json"))),
              without_host_fields(nlohmann::json::parse(read_file(dir / "2/stats.json"))));
    EXPECT_EQ(read_file(dir / "1/config.json"), read_file(dir / "2/config.json"));
}

TEST(Cli, OverridesReachTheMachineAndConfig) {
    const fs::path dir = scratch("overrides");
    const RunResult r = run("render " + scenario("sphere.toml") + " --set gp.count=64 --set ring.clock_mhz=40 --out " +
                                (dir / "out").string(),
                            dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto config = nlohmann::json::parse(read_file(dir / "out/config.json"));
    EXPECT_EQ(config["parameters"]["gp.count"]["value"], 64);
    EXPECT_EQ(config["parameters"]["gp.count"]["origin"], "--set");
    const auto stats = nlohmann::json::parse(read_file(dir / "out/stats.json"));
    EXPECT_TRUE(stats["components"].contains("gp[63]"));
}

// stats.json's timing model names the calibration in force, and the frame line where the time went.
TEST(Cli, TheTimingModelSaysWhichCalibrationIsInForce) {
    const fs::path dir = scratch("calibration_in_force");
    RunResult r = run("render " + scenario("sphere.toml") + " --out " + (dir / "plain").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto summary = nlohmann::json::parse(read_file(dir / "plain/stats.json"))["summary"];
    EXPECT_NE(summary["timing_model"].get<std::string>().find("uncalibrated (every calibration scale 1)"),
              std::string::npos)
        << summary;
    EXPECT_NE(r.output.find("time: PPs "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("% busy"), std::string::npos) << r.output;

    r = run("render " + scenario("sphere.toml") + " --set calibration.gp_flops_scale=2.5 --out " +
                (dir / "scaled").string(),
            dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    summary = nlohmann::json::parse(read_file(dir / "scaled/stats.json"))["summary"];
    const std::string model = summary["timing_model"];
    EXPECT_NE(model.find("calibration.gp_flops_scale = 2.5 (from --set)"), std::string::npos) << model;
    EXPECT_EQ(model.find("uncalibrated"), std::string::npos) << model;
}

// A bad input: exit 2, one error line naming the file and the field, and no output directory.
void expect_rejected(const std::string& name, const std::string& args, const std::string& must_mention) {
    const fs::path dir = scratch(name);
    const RunResult r = run(args + " --out " + (dir / "out").string(), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("pp5sim: error:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(must_mention), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << "output written despite the error";
}

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
}

TEST(Cli, BadScenarioIsRejected) {
    const fs::path dir = scratch("bad_scenario_files");
    const std::string good = read_file(scenario("sphere.toml"));
    auto misspelt = write(dir, "misspelt.toml", good + "\n[camera]\nazimut = 3\n");
    expect_rejected("misspelt", "render " + misspelt.string(), "camera.azimut");
    auto range = write(dir, "range.toml", good + "\n[shading]\nshininess = -1\n");
    expect_rejected("range", "render " + range.string(), "shading.shininess");
    auto syntax = write(dir, "syntax.toml", "[scenario\n");
    expect_rejected("syntax", "render " + syntax.string(), "syntax.toml");
    auto phantom =
        write(dir, "phantom.toml", "[dataset]\nphantom = \"cube\"\n[classification]\ncontours = [{value = 1}]\n");
    expect_rejected("phantom", "render " + phantom.string(), "dataset.phantom");
    expect_rejected("missing", "render /no/such/scenario.toml", "/no/such/scenario.toml");
}

TEST(Cli, BadMachineIsRejected) {
    const fs::path dir = scratch("bad_machine_files");
    auto machine = write(dir, "machine.toml", "[ring]\nchannels = 0\n");
    expect_rejected("machine_range", "render " + scenario("sphere.toml") + " --machine " + machine.string(),
                    "ring.channels");
    expect_rejected("machine_key", "render " + scenario("sphere.toml") + " --set gp.cout=2", "gp.cout");
    // A machine too small for the volume: the error says what it would need.
    expect_rejected(
        "machine_small",
        "render " + scenario("sphere.toml") + " --set renderer.count=1 --set renderer.backing_store_bits=512",
        "renderer.backing_store_bits");
    expect_rejected("kernel_setting", "render " + scenario("sphere.toml") + " --set voxel_store.placement=diagonal",
                    "voxel_store.placement");
    // When the scenario gives the volume's size, a machine that cannot hold it is refused before the
    // volume is read: here the raw file does not even exist, and the error is the machine's.
    const fs::path big_dir = scratch("too_big_files");
    const auto too_big =
        write(big_dir, "too_big.toml",
              "[dataset]\nfile = \"absent.raw\"\nraw = { dims = [2048, 2048, 2048], type = \"uint8\" }\n"
              "[classification]\ncontours = [{value = 100}]\n");
    expect_rejected("too_big", "render " + too_big.string(), "renderer.backing_store_bits");
    // Placed on 1024 renderers, a 1024^3 volume's pyramid (153 MB a GP) outgrows the GPs' memory.
    const auto big_pyramid =
        write(big_dir, "big_pyramid.toml",
              "[dataset]\nfile = \"absent.raw\"\nraw = { dims = [1024, 1024, 1024], type = \"uint8\" }\n"
              "[classification]\ncontours = [{value = 100}]\n");
    expect_rejected("too_big_pyramid", "render " + big_pyramid.string() + " --set renderer.count=1024",
                    "gp.memory_bytes");
    // Yuan's kernel: a negative radius, bands of no depth, a switch out of range, a cut-off too tight.
    const std::string yuan = "render " + scenario("yuan-checker-box.toml");
    expect_rejected("yuan_radius", yuan + " --set yuan.kernel_radius=-1", "yuan.kernel_radius");
    expect_rejected("yuan_bands", yuan + " --set yuan.band_voxels=0", "yuan.band_voxels");
    expect_rejected("yuan_switch", yuan + " --set yuan.switch_pixels=1000", "yuan.switch_pixels");
    expect_rejected("yuan_sigma", yuan + " --set yuan.kernel_sigma=2 --set yuan.kernel_radius=2", "yuan.kernel_sigma");
    // And a scenario asking it for what it cannot draw: the volume-of-interest tool.
    const fs::path yuan_dir = scratch("yuan_region_files");
    const auto with_region =
        write(yuan_dir, "region.toml",
              "[scenario]\nkernel = \"yuan\"\n[dataset]\nphantom = \"sphere\"\nsize = 24\n[classification]\n"
              "contours = [{value = 100}]\n[region]\nshape = \"box\"\ncenter = [12, 12, 12]\nhalf_size = [4, 4, 4]\n");
    expect_rejected("yuan_region", "render " + with_region.string(), "region");
    // Stationary lights: refused by the kernels whose GP costs count one light, and, on the levoy
    // kernel, their record field refused by name when only it keeps the volume out of the backing store.
    const std::string lights =
        "[dataset]\nphantom = \"sphere\"\nsize = 24\n[classification]\ncontours = [{value = 100}]\n"
        "[image]\nresampling = \"interpolate-then-shade\"\n"
        "[shading]\nstationary_lights = [{ direction = [1, 0, 0] }]\n";
    const auto perm_lights = write(yuan_dir, "perm_lights.toml", "[scenario]\nkernel = \"perm\"\n" + lights);
    expect_rejected("perm_lights", "render " + perm_lights.string(), "shading.stationary_lights");
    std::string wilson_text = "[scenario]\nkernel = \"wilson\"\n" + lights;
    wilson_text.replace(wilson_text.find("interpolate-then-shade"), std::string("interpolate-then-shade").size(),
                        "shade-then-interpolate");
    const auto wilson_lights = write(yuan_dir, "wilson_lights.toml", wilson_text);
    expect_rejected("wilson_lights", "render " + wilson_lights.string(), "shading.stationary_lights");
    const auto big_lights =
        write(big_dir, "big_lights.toml",
              "[dataset]\nfile = \"absent.raw\"\nraw = { dims = [512, 512, 60], type = \"uint8\" }\n"
              "[classification]\ncontours = [{value = 100}]\n"
              "[shading]\nstationary_lights = [{ direction = [1, 0, 0] }]\n");
    expect_rejected("too_big_lights", "render " + big_lights.string(), "levoy.stationary_light_bits");
}

TEST(Cli, BadVolumeIsRejected) {
    const fs::path dir = scratch("bad_volume_files");
    // A NIfTI header cut short.
    auto truncated = write(dir, "truncated.nii", std::string(100, '\0'));
    const std::string scenario_text =
        "[dataset]\nfile = \"truncated.nii\"\n[classification]\ncontours = [{value = 1}]\n";
    auto s = write(dir, "uses_truncated.toml", scenario_text);
    expect_rejected("truncated", "render " + s.string(), "truncated.nii");
    // A raw file whose size does not match its dimensions and type.
    write(dir, "short.raw", std::string(999, '\1'));
    s = write(dir, "uses_raw.toml",
              "[dataset]\nfile = \"short.raw\"\nraw = { dims = [10, 10, 10], type = \"uint8\" }\n"
              "[classification]\ncontours = [{value = 1}]\n");
    expect_rejected("raw_size", "render " + s.string(), "short.raw");
    const RunResult info = run("volume-info " + truncated.string(), dir);
    EXPECT_EQ(info.exit_code, 2) << info.output;
    EXPECT_NE(info.output.find("truncated.nii"), std::string::npos) << info.output;
}

TEST(Cli, ParamsListsEveryParameterWithProvenance) {
    const fs::path dir = scratch("params");
    const RunResult r = run("params --json", dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto params = nlohmann::json::parse(r.output);
    bool saw_backing_store = false;
    for (const auto& p : params) {
        EXPECT_FALSE(p["doc"].get<std::string>().empty()) << p["key"];
        EXPECT_FALSE(p["provenance"].get<std::string>().empty()) << p["key"];
        if (p["key"] == "renderer.backing_store_bits") {
            saw_backing_store = true;
            EXPECT_EQ(p["default"], 4096);
            EXPECT_EQ(p["unit"], "bits");
        }
    }
    EXPECT_TRUE(saw_backing_store);
    const RunResult text = run("params", dir);
    EXPECT_EQ(text.exit_code, 0);
    EXPECT_NE(text.output.find("ring.channel_width_bits"), std::string::npos);
}

// `--pictures` adds what a lecture shows beside each frame: the refinement passes as a strip and an
// animated GIF (one image per pass), the map of which GP cast which tile, and the utilisation over time.
TEST(Cli, RenderWritesLecturePicturesOnRequest) {
    const fs::path dir = scratch("pictures");
    const RunResult r =
        run("render " + scenario("head-phantom.toml") + " --pictures --out " + (dir / "out").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto stats = nlohmann::json::parse(read_file(dir / "out/stats.json"));
    const std::size_t passes = stats["frames"][0]["machine"]["passes"].size();
    ASSERT_GE(passes, 2u);
    const std::string gif = read_file(dir / "out/frame_0000_passes.gif");
    EXPECT_EQ(gif.substr(0, 6), "GIF89a");
    std::size_t images = 0;  // each image of an animated GIF has an image descriptor after a graphic control block
    for (std::size_t at = gif.find("\x21\xF9\x04"); at != std::string::npos; at = gif.find("\x21\xF9\x04", at + 1))
        ++images;
    EXPECT_EQ(images, passes);
    EXPECT_TRUE(fs::exists(dir / "out/frame_0000_passes_strip.png"));
    EXPECT_TRUE(fs::exists(dir / "out/frame_0000_gp_tiles.png"));
    EXPECT_EQ(read_file(dir / "out/frame_0000_utilisation.png").substr(1, 3), "PNG");
    // Without the flag, none of them, and the same statistics: recording the busy spans only observes.
    const RunResult plain = run("render " + scenario("head-phantom.toml") + " --out " + (dir / "plain").string(), dir);
    ASSERT_EQ(plain.exit_code, 0) << plain.output;
    EXPECT_FALSE(fs::exists(dir / "plain/frame_0000_passes.gif"));
    EXPECT_FALSE(fs::exists(dir / "plain/frame_0000_utilisation.png"));
    EXPECT_EQ(without_host_fields(nlohmann::json::parse(read_file(dir / "plain/stats.json"))),
              without_host_fields(stats));
}

// Without gnuplot a plot costs only its picture: the run succeeds, says so, and keeps the plot's data
// and gnuplot script beside the other outputs.
TEST(Cli, WithoutGnuplotAPlotKeepsItsDataAndScript) {
    const fs::path dir = scratch("no_gnuplot");
    const fs::path empty_path = dir / "bin";  // a PATH on which no gnuplot can be found
    fs::create_directories(empty_path);
    const RunResult r = run_with_path(empty_path, "render sphere --pictures --out " + (dir / "out").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("warning: frame_0000_utilisation.png not drawn"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out/frame_0000_utilisation.png"));
    EXPECT_NE(read_file(dir / "out/frame_0000_utilisation.gp").find("frame_0000_utilisation.dat"), std::string::npos);
    EXPECT_FALSE(read_file(dir / "out/frame_0000_utilisation.dat").empty());
    EXPECT_TRUE(fs::exists(dir / "out/frame_0000_gp_tiles.png"));
    EXPECT_TRUE(fs::exists(dir / "out/stats.json"));
}

// serve refuses what it cannot do before it renders or listens.
TEST(Cli, ServeRefusesBadOptionsUpFront) {
    const fs::path dir = scratch("serve");
    for (const char* args : {"serve sphere --port 70000", "serve sphere --image-size 5", "serve sphere --port -1",
                             "serve no-such-scenario", "serve sphere --host 203.0.113.9 --port 0"}) {
        const RunResult r = run(args, dir);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_NE(r.output.find("error"), std::string::npos) << args << ": " << r.output;
    }
}

TEST(Cli, HelpOnEveryCommand) {
    const fs::path dir = scratch("help");
    for (const char* command : {"--help", "render --help", "params --help", "volume-info --help", "fit --help",
                                "reproduce --help", "serve --help"}) {
        const RunResult r = run(command, dir);
        EXPECT_EQ(r.exit_code, 0) << command << r.output;
        EXPECT_NE(r.output.find("Usage"), std::string::npos) << command << r.output;
    }
}

// A small calibration a user could write: a sphere scenario on a small machine, targets for it, and a
// Sun-like uniprocessor; `reproduce` writes the table, the images and the plots.
fs::path write_small_calibration(const fs::path& dir, const std::string& extra_row) {
    std::ofstream(dir / "small.toml") << "[gp]\ncount = 4\n[renderer]\ncount = 4\npp_columns = 32\npp_rows = 32\n";
    std::ofstream(dir / "uni.toml")
        << "[machine]\nname = \"uni\"\nkind = \"uniprocessor\"\n[gp]\ncount = 1\nsustained_mflops = 2.0\n"
           "[renderer]\ncount = 4\npp_columns = 32\npp_rows = 32\n";
    std::ofstream(dir / "frames.toml")
        << "[scenario]\nname = \"frames\"\n[dataset]\nphantom = \"sphere\"\nsize = 40\n"
           "[classification]\nkind = \"piecewise-linear\"\n"
           "points = [{ value = 50.0, opacity = 0.0 }, { value = 150.0, opacity = 0.8 }]\n"
           "[image]\nwidth = 48\nheight = 48\n"
           "[[frames]]\nlabel = \"first\"\n[[frames]]\nlabel = \"orbit\"\ncamera = { azimuth = 15.0 }\n";
    const auto row = [&](const std::string& id, int frame, const std::string& machine, const std::string& metric,
                         double value, const std::string& use) {
        return "[[targets]]\nid = \"" + id + "\"\nsource = \"test\"\nscenario = \"" + (dir / "frames.toml").string() +
               "\"\nframe = " + std::to_string(frame) + "\nmachine = \"" + (dir / machine).string() +
               "\"\nmetric = \"" + metric + "\"\nreported = " + std::to_string(value) +
               "\nexactness = \"estimate\"\nuse = \"" + use + "\"\n";
    };
    const fs::path targets = dir / "targets.toml";
    std::ofstream(targets) << "[calibration]\nname = \"small\"\n"
                           << row("a", 0, "small.toml", "crude_seconds", 0.05, "fit")
                           << row("b", 0, "small.toml", "refined_seconds", 0.2, "fit")
                           << row("c", 1, "small.toml", "refined_seconds", 0.1, "fit")
                           << row("d", 0, "small.toml", "pp_seconds", 0.01, "fit")
                           << row("e", 1, "small.toml", "crude_seconds", 0.02, "held-out")
                           << row("f", 1, "uni.toml", "crude_seconds", 0.5, "fit")
                           << row("g", 1, "uni.toml", "refined_seconds", 2.0, "fit")
                           << row("h", 0, "uni.toml", "crude_seconds", 0.6, "fit") << extra_row;
    return targets;
}

TEST(Cli, ReproduceWritesTheTableImagesAndPlots) {
    const fs::path dir = scratch("reproduce");
    const fs::path targets = write_small_calibration(dir, "");
    const RunResult r =
        // One timed run per host-check case: the check's path is what is tested here, not its timings.
        run("reproduce --targets " + targets.string() + " --gp-counts 1,4,16 --repeats 1 --out " +
                (dir / "out").string(),
            dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const char* file : {"reproduction.md", "reproduction.json", "fit.md", "fit.json", "small-fitted.toml",
                             "uni-fitted.toml", "reported_vs_simulated_seconds.png", "reported_vs_simulated_seconds.gp",
                             "frame_time_vs_gps.png", "frame_time_vs_gps.json", "host_check.md", "host_check.json"})
        EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;
    const auto table = nlohmann::json::parse(read_file(dir / "out/reproduction.json"));
    ASSERT_EQ(table["rows"].size(), 8u);
    for (const auto& row : table["rows"]) {
        EXPECT_GT(row["simulated"].get<double>(), 0.0) << row;
        EXPECT_NEAR(row["relative_error"].get<double>(),
                    (row["simulated"].get<double>() - row["reported"].get<double>()) / row["reported"].get<double>(),
                    1e-12);
        EXPECT_TRUE(row["use"] == "fit" || row["use"] == "held-out") << row;
        EXPECT_TRUE(row["group"] == "fitted" || row["group"] == "predicted") << row;
        EXPECT_GT(row["uncalibrated"].get<double>(), 0.0) << row;  // the documented costs' value beside the fit's
        // with its interval over the documented guesses' plausible ranges
        EXPECT_LT(row["uncalibrated_low"].get<double>(), row["uncalibrated"].get<double>()) << row;
        EXPECT_GT(row["uncalibrated_high"].get<double>(), row["uncalibrated"].get<double>()) << row;
    }
    // The claims checked across the range, on the one multicomputer: re-timed at their worst, never better than as
    // configured.
    ASSERT_EQ(table["conclusions"].size(), 2u) << table["conclusions"];
    EXPECT_GE(table["conclusions"][0]["at_worst"].get<double>(),
              table["conclusions"][0]["as_configured"].get<double>());
    EXPECT_LE(table["conclusions"][1]["at_worst"].get<double>(),
              table["conclusions"][1]["as_configured"].get<double>());
    EXPECT_NE(read_file(dir / "out/reproduction.md").find("## What holds across the plausible range"),
              std::string::npos);
    // Errors judged by unit: every row here is in seconds.
    EXPECT_EQ(table["summary"]["by_unit"]["s"]["count"].get<int>(), 8) << table["summary"];
    const auto sweep = nlohmann::json::parse(read_file(dir / "out/frame_time_vs_gps.json"));
    ASSERT_EQ(sweep["points"].size(), 3u);
    // More GPs never make the crude frame slower here.
    EXPECT_GE(sweep["points"][0]["crude_seconds"].get<double>(), sweep["points"][2]["crude_seconds"].get<double>());
    EXPECT_NE(read_file(dir / "out/fit.md").find("| a | "), std::string::npos);
}

// Levoy's MR head sequence (orbit, then a light move with the observer still): with the GPs asking
// again for the blocks they used (levoy.after_reshade = refresh), the light frame sends fewer fetch
// requests than the orbit frame before it, and far fewer than when the GPs drop their caches.
TEST(Cli, OnTheMrHeadSequenceALightChangeThatRefreshesSendsFewerFetchesThanAnOrbit) {
    const fs::path dir = scratch("refresh_sequence");
    // The shipped sequence up to its light move, at 256x256 (a third of the host time of all of it).
    std::string text = read_file(scenario("mr-head-sequence.toml"));
    const auto replace = [&](const std::string& from, const std::string& to) {
        const auto at = text.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        text.replace(at, from.size(), to);
    };
    replace("width = 512\nheight = 512", "width = 256\nheight = 256");
    const auto colour_change = text.find("[[frames]]\nlabel = \"classification keeps");
    ASSERT_NE(colour_change, std::string::npos);
    text.erase(colour_change);
    const fs::path sequence = dir / "sequence.toml";
    std::ofstream(sequence) << text;

    const auto requests = [&](const std::string& after_reshade) {
        const fs::path out = dir / after_reshade;
        const RunResult r =
            run("render " + sequence.string() + " --no-reference --set levoy.after_reshade=" + after_reshade +
                    " --out " + out.string(),
                dir);
        EXPECT_EQ(r.exit_code, 0) << r.output;
        const auto stats = nlohmann::json::parse(read_file(out / "stats.json"));
        const auto& frames = stats["frames"];
        EXPECT_EQ(frames[2]["label"], "observer moved again");
        EXPECT_EQ(frames[3]["label"], "light moved");
        return std::pair{frames[2]["machine"]["fetch_requests"].get<std::uint64_t>(),
                         frames[3]["machine"]["fetch_requests"].get<std::uint64_t>()};
    };
    const auto [orbit, light] = requests("refresh");
    const auto [orbit_dropping, light_dropping] = requests("drop");
    EXPECT_EQ(orbit, orbit_dropping);  // nothing changed before the light did
    EXPECT_LT(light, orbit);
    EXPECT_LT(light, light_dropping);
}

// The default ray assignment (interleaved tiles) on Levoy's MR head at his 32 GPs: every GP casts, and
// none more than three times another (raster-order tiles left whole columns of GPs idle).
TEST(Cli, OnTheMrHeadEveryOneOfThe32GpsCasts) {
    const fs::path dir = scratch("balanced_gps");
    const RunResult r = run("render mr-head --no-reference --out " + (dir / "out").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto stats = nlohmann::json::parse(read_file(dir / "out/stats.json"));
    ASSERT_EQ(stats["frames"].size(), 1u);  // so each GP's counters are that frame's
    std::uint64_t fewest = ~0ull, most = 0;
    for (int g = 0; g < 32; ++g) {
        const auto items = stats["components"]["gp[" + std::to_string(g) + "]"]["items"]["value"].get<std::uint64_t>();
        fewest = std::min(fewest, items);
        most = std::max(most, items);
    }
    EXPECT_FALSE(stats["components"].contains("gp[32]"));
    EXPECT_GT(fewest, 0u);
    EXPECT_LT(most, 3 * fewest) << fewest << ".." << most;
}

TEST(Cli, RenderRefusesAUniprocessorMachine) {
    const fs::path dir = scratch("render_sun");
    const RunResult r = run("render sphere --machine sun4-280 --out " + (dir / "out").string(), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("machine.kind"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Cli, FitRejectsABadTargetFileBeforeAnyOutput) {
    const fs::path dir = scratch("fit_bad");
    const fs::path targets = write_small_calibration(dir,
                                                     "[[targets]]\nid = \"z\"\nsource = \"x\"\nscenario = \"nowhere\"\n"
                                                     "machine = \"pxpl5\"\nmetric = \"crude_seconds\"\nreported = 1.0\n"
                                                     "exactness = \"estimate\"\nuse = \"fit\"\n");
    const RunResult r = run("fit --targets " + targets.string() + " --out " + (dir / "out").string(), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("targets[8].scenario"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// A sweep as a user runs it: a shipped sweep file writes its CSV, JSON and plot; under mpirun each
// rank writes its shard and --merge joins them into the same bytes; a bad sweep writes nothing.
TEST(Cli, SweepWritesItsTablesAndMpiShardsMergeToTheSameBytes) {
    const fs::path dir = scratch("sweep");
    const RunResult whole = run("sweep phantom-gps --out " + (dir / "whole").string(), dir);
    ASSERT_EQ(whole.exit_code, 0) << whole.output;
    EXPECT_NE(whole.output.find("7 of 7 points"), std::string::npos) << whole.output;
    for (const char* f : {"sweep.csv", "sweep.json", "sweep_head-phantom.png", "sweep_head-phantom.gp"})
        EXPECT_TRUE(fs::exists(dir / "whole" / f)) << f;
    const std::string csv = read_file(dir / "whole/sweep.csv");
    EXPECT_EQ(
        csv.substr(0, csv.find('\n'))
            .find(
                "point,scenario,gp.count,levoy.ray_assignment,ring.clock_mhz,frame,label,status,simulated_seconds [s]"),
        0u)
        << csv.substr(0, 300);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 7 * 2);  // a row per point and frame

    const RunResult bad = run("sweep --scenario head-phantom --vary gp.count=4,x --out " + (dir / "bad").string(), dir);
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    EXPECT_NE(bad.output.find("vary.gp.count[1]"), std::string::npos) << bad.output;
    EXPECT_FALSE(fs::exists(dir / "bad"));

    if (std::system("command -v mpirun > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "mpirun absent: apt-get install openmpi-bin";
    // Open MPI refuses root without these (CI containers run as root) and two ranks on a small host
    // without --oversubscribe.
    const std::string mpirun =
        "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -n 2 ";
    const std::string shards = (dir / "ranks").string();
    const int status = std::system((mpirun + PP5SIM_BINARY + " sweep phantom-gps --threads 1 --out " + shards + " > " +
                                    (dir / "mpi.txt").string() + " 2>&1")
                                       .c_str());
    ASSERT_EQ(status, 0) << read_file(dir / "mpi.txt");
    EXPECT_TRUE(fs::exists(dir / "ranks/shard-0-of-2.json"));
    EXPECT_TRUE(fs::exists(dir / "ranks/shard-1-of-2.json"));
    const RunResult merged = run("sweep --merge " + shards, dir);
    ASSERT_EQ(merged.exit_code, 0) << merged.output;
    EXPECT_EQ(read_file(dir / "ranks/sweep.json"), read_file(dir / "whole/sweep.json"));
    EXPECT_EQ(read_file(dir / "ranks/sweep.csv"), csv);
}

// With --uncertainty every metric but a count gets its 95% band, the frame time's around it, measured
// at the same point whichever shard runs it, so shards still merge to the whole sweep's bytes.
TEST(Cli, SweepBandsHoldTheirFiguresAndShardsMergeToTheSameBands) {
    const fs::path dir = scratch("sweep_bands");
    const RunResult whole = run("sweep phantom-gps --uncertainty --out " + (dir / "whole").string(), dir);
    ASSERT_EQ(whole.exit_code, 0) << whole.output;
    EXPECT_NE(whole.output.find("bands: "), std::string::npos) << whole.output;
    const nlohmann::json sweep = nlohmann::json::parse(read_file(dir / "whole/sweep.json"));
    ASSERT_TRUE(sweep["sweep"].contains("uncertainty"));
    EXPECT_EQ(sweep["sweep"]["uncertainty"]["measured_at_points"].size(), 3u);  // one per recording group
    std::size_t checked = 0;
    for (const auto& point : sweep["results"])
        for (const auto& frame : point["frames"]) {
            const auto& m = frame["metrics"];
            EXPECT_FALSE(m.contains("events_low")) << "a count has no band";
            EXPECT_LT(m["simulated_seconds_low"].get<double>(), m["simulated_seconds"].get<double>());
            EXPECT_GT(m["simulated_seconds_high"].get<double>(), m["simulated_seconds"].get<double>());
            ++checked;
        }
    EXPECT_EQ(checked, 7u * 2u);
    for (const char* shard : {"0/2", "1/2"}) {
        const RunResult part =
            run(std::string("sweep phantom-gps --uncertainty --shard ") + shard + " --out " + (dir / "parts").string(),
                dir);
        ASSERT_EQ(part.exit_code, 0) << part.output;
    }
    const RunResult merged = run("sweep --merge " + (dir / "parts").string(), dir);
    ASSERT_EQ(merged.exit_code, 0) << merged.output;
    EXPECT_EQ(read_file(dir / "parts/sweep.csv"), read_file(dir / "whole/sweep.csv"));
}

// render --uncertainty: each frame's line and record carry the band, and stats.json names the guesses.
TEST(Cli, RenderGivesEachFrameItsBandAndTheGuessesThatSetIt) {
    const fs::path dir = scratch("render_bands");
    const RunResult r = run("render head-phantom --uncertainty --no-reference --out " + (dir / "out").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("[95% over the guesses' ranges: "), std::string::npos) << r.output;
    const nlohmann::json stats = nlohmann::json::parse(read_file(dir / "out/stats.json"));
    ASSERT_TRUE(stats.contains("uncertainty"));
    EXPECT_GT(stats["uncertainty"]["guesses"].size(), 10u);
    for (const auto& frame : stats["frames"]) {
        const auto& band = frame["uncertainty"];
        EXPECT_LT(band["simulated_seconds_low"].get<double>(), frame["simulated_seconds"].get<double>());
        EXPECT_GT(band["simulated_seconds_high"].get<double>(), frame["simulated_seconds"].get<double>());
        EXPECT_LE(band["every_guess_at_its_worst"][0].get<double>(), band["simulated_seconds_low"].get<double>());
        EXPECT_FALSE(band["main_guesses"].empty());
    }
}

// JSON nested far deeper than any file pp5sim writes is refused as bad input by every command that
// reads a user's JSON, before anything walks it (the walk recurses and would overflow the stack).
TEST(Cli, DeeplyNestedJsonIsRefusedByCompareAndMerge) {
    const fs::path dir = scratch("deep_json");
    fs::create_directories(dir / "shards");
    std::ofstream(dir / "deep.json") << std::string(50000, '[') << std::string(50000, ']');
    std::ofstream(dir / "shards/shard-0-of-1.json") << std::string(50000, '{');
    const RunResult compare = run("compare " + (dir / "deep.json").string() + " " + (dir / "deep.json").string(), dir);
    EXPECT_EQ(compare.exit_code, 2) << compare.output;
    EXPECT_NE(compare.output.find("deep.json: compare: nests arrays and objects more than"), std::string::npos)
        << compare.output;
    const RunResult merge = run("sweep --merge " + (dir / "shards").string(), dir);
    EXPECT_EQ(merge.exit_code, 2) << merge.output;
    EXPECT_NE(merge.output.find("shard-0-of-1.json: shard: "), std::string::npos) << merge.output;
}

// A value refused once the run has started (by a component or a kernel, not by the machine file's
// reader) is named with where it came from: the machine file, or --set.
TEST(Cli, AValueRefusedWhenTheRunStartsNamesTheFileOrOptionThatGaveIt) {
    const fs::path dir = scratch("origins");
    std::ofstream(dir / "odd.toml") << "[perm]\nindex_bytes = 3\n";
    const RunResult from_file = run(
        "render perm-head-phantom --machine " + (dir / "odd.toml").string() + " --out " + (dir / "a").string(), dir);
    EXPECT_EQ(from_file.exit_code, 2) << from_file.output;
    EXPECT_NE(from_file.output.find("odd.toml: perm.index_bytes: must be 2"), std::string::npos) << from_file.output;
    const RunResult from_set =
        run("render perm-head-phantom --set perm.index_bytes=3 --out " + (dir / "a").string(), dir);
    EXPECT_EQ(from_set.exit_code, 2) << from_set.output;
    EXPECT_NE(from_set.output.find("error: --set: perm.index_bytes: must be 2"), std::string::npos) << from_set.output;
    EXPECT_FALSE(fs::exists(dir / "a"));
}

// The up-front memory checks compare with what this process may use: under an address-space limit
// (ulimit -v, as a batch job may set) a volume is refused at half of the limit, saying which limit.
// The sanitizers reserve terabytes of address space, so this runs only in the plain builds.
TEST(Cli, MemoryChecksUseTheProcessLimitNotOnlyThePhysicalMemory) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    GTEST_SKIP() << "an address-space limit cannot be set under a sanitizer";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
    GTEST_SKIP() << "an address-space limit cannot be set under a sanitizer";
#endif
#endif
    const fs::path dir = scratch("memory_limit");
    std::ofstream(dir / "big.toml")
        << "[scenario]\nname = \"big\"\n[dataset]\nphantom = \"sphere\"\nsize = 640\n"
           "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 50.0, opacity = 0.0 }, "
           "{ value = 150.0, opacity = 0.8 }]\n[image]\nwidth = 64\nheight = 64\n";
    const RunResult limited = run_command("ulimit -v 1500000; " + std::string(PP5SIM_BINARY) + " render " +
                                              (dir / "big.toml").string() + " --out " + (dir / "out").string(),
                                          dir);
    EXPECT_EQ(limited.exit_code, 2) << limited.output;
    EXPECT_NE(limited.output.find("big.toml: dataset.size: loading a 640x640x640 volume"), std::string::npos)
        << limited.output;
    EXPECT_NE(limited.output.find("this process may use 1.5 GB, set by its address-space limit (ulimit -v)"),
              std::string::npos)
        << limited.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// Float samples at the ends of float's range (their differences and sums overflow a float) render on
// every kernel: gradients, statistics and classification stay finite.
TEST(Cli, FloatVolumesAtTheEndsOfTheRangeRenderOnEveryKernel) {
    const fs::path dir = scratch("float_extremes");
    std::vector<float> samples;
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                samples.push_back((x * y + z) % 3 == 0 ? 3.4e38f : (x + y) % 3 == 1 ? -3.4e38f : 1.0f);
    std::ofstream(dir / "extremes.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(samples.data()),
               static_cast<std::streamsize>(samples.size() * sizeof(float)));
    for (const std::string kernel : {"levoy", "yuan", "wilson", "perm"}) {
        std::ofstream(dir / (kernel + ".toml"))
            << "[scenario]\nname = \"extremes-" << kernel << "\"\nkernel = \"" << kernel << "\"\n"
            << "[dataset]\nfile = \"extremes.raw\"\n[dataset.raw]\ndims = [16, 16, 16]\ntype = \"float32\"\n"
            << "[classification]\nkind = \"piecewise-linear\"\n"
            << "points = [{ value = 0.0, opacity = 0.0 }, { value = 1e9, opacity = 0.8 }]\n"
            << "[image]\nwidth = 32\nheight = 32\n"
            << (kernel == "perm" ? "resampling = \"interpolate-then-shade\"\n" : "");
        const RunResult r =
            run("render " + (dir / (kernel + ".toml")).string() + " --out " + (dir / kernel).string(), dir);
        EXPECT_EQ(r.exit_code, 0) << kernel << ": " << r.output;
        EXPECT_TRUE(fs::exists(dir / kernel / "stats.json")) << kernel;
    }
}

// compare-kernels: every kernel that runs on the machine renders the same scenario; the report lists
// each with its picture and figures, or with why it refused; PERM renders in its own resampling order.
TEST(Cli, CompareKernelsReportsEveryKernelOnOneScenario) {
    const fs::path dir = scratch("compare_kernels");
    const RunResult r = run("compare-kernels sphere --out " + (dir / "report").string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto report = nlohmann::json::parse(read_file(dir / "report/report.json"));
    EXPECT_EQ(report["scenario"], "sphere");
    std::set<std::string> kernels;
    for (const auto& row : report["kernels"]) {
        const std::string name = row["kernel"];
        kernels.insert(name);
        if (row.contains("refusal")) {
            EXPECT_FALSE(row["refusal"].get<std::string>().empty()) << name;
            continue;
        }
        EXPECT_TRUE(fs::exists(dir / "report" / (name + ".png"))) << name;
        EXPECT_GT(row["mean_frame_seconds"].get<double>(), 0.0) << name;
        EXPECT_GT(row["psnr_db"].get<double>(), 20.0) << name;
        EXPECT_FALSE(row["phases_seconds"].empty()) << name;
        EXPECT_GT(row["ring_bytes"].get<double>(), 0.0) << name;
        if (name == "perm") {
            EXPECT_NE(row["adaptation"].get<std::string>().find("interpolate-then-shade"), std::string::npos);
        }
    }
    EXPECT_EQ(kernels, (std::set<std::string>{"levoy", "yuan", "wilson", "perm"}));
    EXPECT_TRUE(fs::exists(dir / "report/side_by_side.png"));
    const std::string md = read_file(dir / "report/report.md");
    for (const std::string& name : kernels) EXPECT_NE(md.find("## " + name), std::string::npos) << name;
}

// compare on two renders that differ in gp.count: the frame times and per-GP figures change, the exit
// status says they differ; a run against itself does not; a missing run is bad input.
TEST(Cli, CompareShowsWhatChangedAndExitsThreeBeyondTheTolerance) {
    const fs::path dir = scratch("compare");
    ASSERT_EQ(run("render head-phantom --out " + (dir / "a").string(), dir).exit_code, 0);
    ASSERT_EQ(run("render head-phantom --set gp.count=16 --out " + (dir / "b").string(), dir).exit_code, 0);
    const RunResult differ =
        run("compare " + (dir / "a").string() + " " + (dir / "b/stats.json").string() + " --tolerance 0.01", dir);
    EXPECT_EQ(differ.exit_code, 3) << differ.output;
    for (const char* changed :
         {"summary/simulated_seconds/0", "frames/0/simulated_seconds", "components/gp[1]/busy_time", "gone"})
        EXPECT_NE(differ.output.find(changed), std::string::npos) << changed << "\n" << differ.output.substr(0, 2000);
    const RunResult same = run("compare " + (dir / "a").string() + " " + (dir / "a").string(), dir);
    EXPECT_EQ(same.exit_code, 0) << same.output;
    const RunResult missing = run("compare " + (dir / "a").string() + " " + (dir / "nowhere").string(), dir);
    EXPECT_EQ(missing.exit_code, 2) << missing.output;

    // Only runs' statistics: two empty objects do not "agree", and a sweep's results are not a run.
    std::ofstream(dir / "empty.json") << "{}";
    const RunResult empty = run("compare " + (dir / "empty.json").string() + " " + (dir / "empty.json").string(), dir);
    EXPECT_EQ(empty.exit_code, 2) << empty.output;
    EXPECT_NE(empty.output.find("empty.json: summary: is missing"), std::string::npos) << empty.output;
    std::ofstream(dir / "sweep.json") << R"({"sweep": {}, "columns": [], "results": []})";
    const RunResult sweep = run("compare " + (dir / "a").string() + " " + (dir / "sweep.json").string(), dir);
    EXPECT_EQ(sweep.exit_code, 2) << sweep.output;
    EXPECT_NE(sweep.output.find("sweep.json: compare: is a sweep's results"), std::string::npos) << sweep.output;
}

// Usage mistakes keep the documented exit code 2, say what was meant when it is close, and counts
// cannot be negative; --version answers.
TEST(Cli, UsageErrorsExitTwoWithADidYouMean) {
    const fs::path dir = scratch("usage");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"rendr sphere", "did you mean render?"},
        {"", "a command is required"},
        {"render sphere --trhead 2", "did you mean --threads?"},
        {"render sphere --threads many", "Could not convert"},
        {"render sphere --trace-limit -1", "\"-1\" is not a whole number from 0"},
        {"volume-info ch2 --header-bytes=-5", "is not a whole number from 0"},
        {"render sphere --format gif", "--format: must be png or exr"},
        {"render spere", "did you mean sphere?"},
        {"render sphere --machine pxpl", "did you mean pxpl5?"},
        {"render sphere --set gp.cont=3", "did you mean gp.count?"},
    };
    for (const auto& [args, says] : cases) {
        const RunResult r = run(args, dir);
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(says), std::string::npos) << args << "\n" << r.output;
        EXPECT_EQ(r.output.find("--format: --format"), std::string::npos) << r.output;
    }
    const RunResult version = run("--version", dir);
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_EQ(version.output.rfind("pp5sim ", 0), 0u) << version.output;
}

// Output paths are checked before any work (a file, a path under a file, /dev/null, a trace under a
// file: exit 2, nothing written); a folder where an output file goes stops the commit before any file
// is written; a rerun with fewer frames leaves none of the last run's; a scenario cannot name its
// output folder "..".
TEST(Cli, OutputsAreCheckedFirstWrittenWholeAndNeverMixed) {
    const fs::path dir = scratch("outputs");
    const fs::path file = dir / "a_file";
    std::ofstream(file) << "x";
    for (const std::string& args :
         {"--out " + file.string(), "--out " + (file / "sub").string(), std::string("--out /dev/null"),
          "--out " + (dir / "t").string() + " --trace " + (file / "trace.json").string()}) {
        const RunResult r = run("render sphere " + args, dir);
        EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("host time"), std::string::npos) << args << ": the run went ahead\n" << r.output;
    }
    EXPECT_FALSE(fs::exists(dir / "t"));

    const fs::path out = dir / "run";
    ASSERT_EQ(run("render head-phantom --out " + out.string(), dir).exit_code, 0);
    EXPECT_TRUE(fs::exists(out / "frame_0003.png"));
    ASSERT_EQ(run("render sphere --out " + out.string() + " --trace " + (dir / "trace.json").string(), dir).exit_code,
              0);
    EXPECT_TRUE(fs::exists(out / "frame_0000.png"));
    EXPECT_FALSE(fs::exists(out / "frame_0003.png")) << "the last run's frames were left beside this one's";
    EXPECT_TRUE(fs::exists(dir / "trace.json"));
    EXPECT_EQ(nlohmann::json::parse(read_file(out / "stats.json"))["summary"]["scenario"], "sphere");

    const fs::path blocked = dir / "blocked";
    fs::create_directories(blocked / "stats.json");
    const RunResult r = run("render sphere --out " + blocked.string(), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("is a folder where pp5sim would write a file"), std::string::npos) << r.output;
    for (const auto& entry : fs::directory_iterator(blocked))
        EXPECT_EQ(entry.path().filename(), "stats.json") << entry.path();

    const fs::path escape = dir / "escape.toml";
    std::string text = read_file(scenario("sphere.toml"));
    text.replace(text.find("name = \"sphere\""), 15, "name = \"..\"");
    std::ofstream(escape) << text;
    const RunResult up = run("render " + escape.string(), dir);
    EXPECT_EQ(up.exit_code, 2) << up.output;
    EXPECT_NE(up.output.find("scenario.name"), std::string::npos) << up.output;
}

// A volume with one voxel along an axis cannot be rendered (samples interpolate between neighbours):
// one line naming the dataset, not an internal error.
TEST(Cli, AVolumeOneVoxelThinIsRefusedAsInput) {
    const fs::path dir = scratch("thin");
    std::ofstream(dir / "thin.raw", std::ios::binary) << std::string(64, '\x40');
    std::ofstream(dir / "thin.toml") << "[dataset]\nfile = \"thin.raw\"\nraw = { dims = [1, 8, 8], type = \"uint8\" }\n"
                                        "[classification]\nkind = \"isovalue-contours\"\ncontours = [{ value = 50.0, "
                                        "opacity = 0.9, thickness = 1.5 }]\n";
    const RunResult r = run("render " + (dir / "thin.toml").string() + " --out " + (dir / "out").string(), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("at least two voxels along each axis"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// A target file with nothing to fit is refused by fit before any scenario is rendered; reproduce
// compares it uncalibrated.
TEST(Cli, FitRefusesATargetFileWithNothingToFit) {
    const fs::path dir = scratch("fit_nothing");
    const RunResult fit = run("fit --targets lim-shin --out " + (dir / "fit").string(), dir);
    EXPECT_EQ(fit.exit_code, 2) << fit.output;
    EXPECT_NE(fit.output.find("nothing to fit"), std::string::npos) << fit.output;
    EXPECT_FALSE(fs::exists(dir / "fit"));
    const RunResult reproduce =
        run("reproduce --targets lim-shin --no-host-check --out " + (dir / "rep").string(), dir);
    EXPECT_EQ(reproduce.exit_code, 0) << reproduce.output;
    EXPECT_NE(reproduce.output.find("uncalibrated"), std::string::npos) << reproduce.output;
}

// `scenarios` lists what can be run by name: every shipped scenario with its kernel, the sweeps, and
// the packaged volumes with whether each is here.
TEST(Cli, ScenariosListsWhatCanBeRunByName) {
    const fs::path dir = scratch("scenarios");
    const RunResult r = run("scenarios", dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const auto& entry : fs::directory_iterator(pp5::test::source_dir() / "traces/scenarios"))
        EXPECT_NE(r.output.find("  " + entry.path().stem().string() + " "), std::string::npos) << entry.path();
    for (const char* listed : {"perm       ", "gp-ring-cache", "ch2 ", "ct-head ", "installed"})
        EXPECT_NE(r.output.find(listed), std::string::npos) << listed;
    EXPECT_EQ(r.output.find("cannot be read"), std::string::npos) << r.output;
}

}  // namespace
