// perm.shading = pp: the renderers' PPs classify and shade PERM's records and the GPs read colours
// and opacities. The picture stays close to the GPs' own shading (the PPs work in fixed point, and
// for a distant viewer), a light change reruns only the shading pass, a record layout that does not
// fit is refused naming the backing store, and the result is the same at any thread count.

#include "frontends/image_io.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/core/input_error.h"
#include "sim/timing/frame_engine.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

Scenario scenario(const std::string& name, const std::string& camera_and_light, const std::string& frames) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("pp5sim_perm_pp_" + std::to_string(::getpid()) + "_" + name + ".toml");
    std::ofstream(path)
        << "[scenario]\nkernel = \"perm\"\n[dataset]\nphantom = \"head\"\nsize = 40\n[classification]\n"
           "kind = \"isovalue-contours\"\ncontours = [{ value = 60.0, opacity = 0.5, thickness = 1.5 }, "
           "{ value = 160.0, opacity = 0.9, thickness = 1.5 }]\n"
        << camera_and_light << "[image]\nwidth = 96\nheight = 96\nresampling = \"interpolate-then-shade\"\n"
        << frames;
    Scenario s = load_scenario(path);
    std::filesystem::remove(path);
    return s;
}

struct Frames {
    std::vector<Image> images;
    std::vector<nlohmann::json> stats;
    std::vector<bool> caches_dropped;
};

Frames render(const Scenario& s, std::vector<std::string> overrides) {
    overrides.push_back("renderer.backing_store_bits=16384");  // the records' positions as 8-byte voxel slots
    const MachineConfig config = load_run_config("pxpl5", overrides);
    Machine machine(config);
    const Volume volume = load_dataset(s);
    auto run = kernel_for(s).start(machine, config, s, volume);
    Frames out;
    for (const FrameSpec& f : s.frames) {
        auto frame = run->record_frame(f);
        const FrameTiming timing = time_frame(machine, frame->work);
        out.images.push_back(frame->pass_images.back());
        out.stats.push_back(run->frame_stats(*frame, timing, {"f.png"}));
        out.caches_dropped.push_back(frame->work.invalidate_gp_caches);
    }
    return out;
}

// Diffuse light from a fixed direction under a parallel camera, depth-cued by k2.
std::string fixed_light(const char* k2 = "0.5") {
    return std::string(
               "[shading]\nambient = 0.2\ndiffuse = 0.7\nspecular = 0.0\nlight_direction = [0.3, 0.5, -1]\ndepth_cue = "
               "[1.0, ") +
           k2 + "]\n[camera]\nprojection = \"parallel\"\nview_from = [0.3, -1.0, 0.4]\nup = [0.0, 0.0, 1.0]\n";
}

TEST(PermPpShading, StaysCloseToTheGpsShadingAndDepthCuesOnTheGps) {
    const Scenario s = scenario("close", fixed_light(), "[[frames]]\nlabel = \"a\"\n");
    const Frames gp = render(s, {}), pp = render(s, {"perm.shading=pp"});
    // No highlight and a parallel view: only the PPs' fixed point differs (and the cue the GP applies).
    const double psnr = compare_images(pp.images[0], gp.images[0]).psnr_db;
    RecordProperty("psnr_pp_vs_gp_db", std::to_string(psnr));
    EXPECT_GT(psnr, 50.0);  // measured 61.7 dB
    EXPECT_TRUE(pp.stats[0]["pp"]["classified"].get<bool>());
    EXPECT_TRUE(pp.stats[0]["pp"]["shaded"].get<bool>());
    EXPECT_GT(pp.stats[0]["pp"]["shading_seconds"].get<double>(), 0.0);
    EXPECT_FALSE(gp.stats[0].contains("pp"));
    // Without the cue applied on the GPs the far side would be as bright as the near.
    const Scenario flat = scenario("flat", fixed_light("0.0"), "[[frames]]\nlabel = \"a\"\n");
    EXPECT_NE(to_rgb8(render(flat, {"perm.shading=pp"}).images[0]), to_rgb8(pp.images[0]));
}

TEST(PermPpShading, ALightChangeReshadesWithoutReclassifyingAndAViewChangeNeither) {
    const Scenario s = scenario("sequence", fixed_light(),
                                "[[frames]]\nlabel = \"first\"\n"
                                "[[frames]]\nlabel = \"light\"\nshading = { light_direction = [-0.6, 1.0, 0.3] }\n"
                                "[[frames]]\nlabel = \"observer\"\ncamera = { azimuth = 40.0 }\n");
    const Frames f = render(s, {"perm.shading=pp"});
    EXPECT_FALSE(f.stats[1]["rebuilt"].get<bool>());
    EXPECT_FALSE(f.stats[1]["pp"]["classified"].get<bool>());
    EXPECT_TRUE(f.stats[1]["pp"]["shaded"].get<bool>());
    EXPECT_FALSE(f.stats[1]["pp"].contains("classification_seconds"));
    EXPECT_TRUE(f.caches_dropped[1]);
    EXPECT_NE(to_rgb8(f.images[1]), to_rgb8(f.images[0]));
    // Diffuse light from a fixed direction does not depend on the observer, and the GPs depth-cue:
    // the PPs' colours stand and the GPs keep what they cached.
    EXPECT_FALSE(f.stats[2]["pp"]["shaded"].get<bool>());
    EXPECT_FALSE(f.caches_dropped[2]);
}

TEST(PermPpShading, RecordsThatDoNotFitTheBackingStoreAreRefused) {
    const Scenario s = scenario("fit", fixed_light(), "[[frames]]\nlabel = \"a\"\n");
    try {
        const MachineConfig config = load_run_config("pxpl5", {"perm.shading=pp", "renderer.backing_store_bits=256"});
        Machine machine(config);
        const Volume volume = load_dataset(s);
        kernel_for(s).start(machine, config, s, volume);
        ADD_FAILURE() << "records that do not fit were accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "renderer.backing_store_bits") << e.what();
        EXPECT_NE(std::string(e.what()).find("perm.shading"), std::string::npos) << e.what();
    }
    try {
        const MachineConfig config = load_run_config("pxpl5", {"perm.shading=pp", "perm.residence=gp_memory"});
        Machine machine(config);
        const Volume volume = load_dataset(s);
        kernel_for(s).start(machine, config, s, volume);
        ADD_FAILURE() << "PP shading of records in GP memory was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "perm.shading") << e.what();
    }
}

TEST(PermPpShading, SamePictureAndTimeAtAnyThreadCount) {
    const Scenario s = scenario("threads", fixed_light(), "[[frames]]\nlabel = \"a\"\n");
    const auto at = [&](std::size_t threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return render(s, {"perm.shading=pp"});
    };
    const Frames one = at(1), two = at(2);
    EXPECT_EQ(to_rgb8(one.images[0]), to_rgb8(two.images[0]));
    EXPECT_EQ(one.stats[0]["simulated_seconds"], two.stats[0]["simulated_seconds"]);
    EXPECT_EQ(one.stats[0]["pp"], two.stats[0]["pp"]);
}

}  // namespace
}  // namespace pp5
