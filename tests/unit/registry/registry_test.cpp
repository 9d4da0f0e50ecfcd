// A kernel is one folder and one registration: the test tree's dummy kernel, registered, renders a
// scenario end to end through the same path as `pp5sim render` (registry, run configuration, timing
// engine, staged output), with its parameters, costs, statistics and metric. Unknown kernels are
// refused, naming the file and listing the known ones.

#include "kernels/registry/registry.h"
#include "dummy_kernel.h"
#include "frontends/render_scenario.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

fs::path write_scenario(const std::string& name, const std::string& kernel) {
    const fs::path dir = fs::temp_directory_path() / ("pp5_registry_test_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path file = dir / "scenario.toml";
    std::ofstream(file) << "[scenario]\nname = \"" << name << "\"\nkernel = \"" << kernel
                        << "\"\n[dataset]\nphantom = \"sphere\"\nsize = 16\n[image]\nwidth = 24\nheight = 16\n"
                           "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 50.0, opacity = 0.0 }, "
                           "{ value = 150.0, opacity = 0.8 }]\n"
                           "[[frames]]\nlabel = \"first\"\n[[frames]]\nlabel = \"again\"\n";
    return file;
}

std::string read_file(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void register_dummy_once() {
    if (find_kernel("dummy") == nullptr) register_kernel(test::dummy_kernel());
}

TEST(Registry, ShipsLevoyAndTheReferenceAndFindsThemByName) {
    ASSERT_NE(find_kernel("levoy"), nullptr);
    ASSERT_NE(find_kernel("reference"), nullptr);
    EXPECT_EQ(find_kernel("levoy")->name(), "levoy");
    EXPECT_TRUE(find_kernel("levoy")->runs_on_machine());
    EXPECT_FALSE(find_kernel("reference")->runs_on_machine());
    EXPECT_EQ(find_kernel("splatting-someday"), nullptr);
}

TEST(Registry, AnUnknownKernelNamesTheFileAndListsTheKnownOnes) {
    const fs::path file = write_scenario("unknown", "no-such-kernel");
    const Scenario scenario = load_scenario(file);
    try {
        (void)kernel_for(scenario);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), file.string());
        EXPECT_EQ(e.field(), "scenario.kernel");
        const std::string what = e.what();
        EXPECT_NE(what.find("no-such-kernel"), std::string::npos) << what;
        EXPECT_NE(what.find("levoy"), std::string::npos) << what;
        EXPECT_NE(what.find("reference"), std::string::npos) << what;
    }
}

TEST(Registry, ADummyKernelRendersEndToEndThroughTheRegistry) {
    register_dummy_once();
    // Its parameters join the run configuration like any kernel's.
    const MachineConfig config =
        load_run_config("pxpl5", {"gp.count=4", "dummy.stripes=3", "gp_cost.dummy.shade_flops=20"});
    EXPECT_EQ(config.integer("dummy.stripes"), 3);

    const fs::path file = write_scenario("dummy", "dummy");
    const Scenario scenario = load_scenario(file);
    const fs::path out = file.parent_path() / "out";
    StagedOutput output(out);
    const ScenarioRender rendered = render_scenario(scenario, config, output);
    output.commit();

    const nlohmann::json stats = nlohmann::json::parse(read_file(out / "stats.json"));
    EXPECT_EQ(stats["summary"]["kernel"], "dummy");
    ASSERT_EQ(stats["frames"].size(), 2u);
    for (const auto& frame : stats["frames"]) {
        EXPECT_EQ(frame["dummy"]["pixels_shaded"], 2 * 24 * 16);
        EXPECT_GT(frame["simulated_seconds"].get<double>(),
                  frame["dummy"]["shade_seconds"].get<double>());  // the broadcast came first
        EXPECT_EQ(frame["dummy"]["pass_images"].size(), 2u);
        EXPECT_TRUE(frame.contains("fidelity"));  // compared with the reference renderer like any machine kernel
    }
    // The machine did the work: the frame buffer counted every pixel of both passes of both frames, the
    // GPs shaded and fetched, the renderers answered, the ring carried broadcasts.
    const nlohmann::json& c = stats["components"];
    EXPECT_EQ(c["frame_buffer"]["pixels_written"]["value"], 2 * 2 * 24 * 16);
    std::uint64_t shaded = 0;
    for (int g = 0; g < 4; ++g)
        shaded += c["gp[" + std::to_string(g) + "]"]["operations.dummy.shade"]["value"].get<std::uint64_t>();
    EXPECT_EQ(shaded, 2u * (2 * 24 * 16 +
                            4 * 100));  // per frame: one per pixel and pass, and 100 after the broadcast on each GP
    EXPECT_GT(c["renderer[0]"]["fetches"]["value"].get<std::uint64_t>(), 0u);
    EXPECT_EQ(c["ring"]["messages"]["value"]["broadcast"], 2 * 16);
    EXPECT_TRUE(fs::exists(out / "frame_0001.png"));
    EXPECT_TRUE(fs::exists(out / "frame_0001_pass_1.png"));
    EXPECT_NE(read_file(out / "config.json").find("gp_cost.dummy.shade_flops"), std::string::npos);
    EXPECT_NE(rendered.lines.back().find("dummy shaded 768 pixels"), std::string::npos) << rendered.lines.back();

    // Its cost parameter changes its time.
    const MachineConfig cheaper = load_run_config("pxpl5", {"gp.count=4", "gp_cost.dummy.shade_flops=5"});
    StagedOutput again(file.parent_path() / "cheaper");
    const ScenarioRender faster = render_scenario(scenario, cheaper, again);
    EXPECT_LT(faster.stats["frames"][0]["dummy"]["shade_seconds"].get<double>(),
              stats["frames"][0]["dummy"]["shade_seconds"].get<double>());
}

TEST(Registry, AKernelRefusesWhatItCannotRender) {
    register_dummy_once();
    const fs::path file = write_scenario("dummy-polygons", "dummy");
    std::ofstream(file, std::ios::app) << "[[polygons]]\nvertices = [[1.0, 1.0, 1.0], [5.0, 1.0, 1.0], [1.0, 5.0, "
                                          "1.0]]\ncolor = [1.0, 1.0, 1.0]\nopacity = 1.0\n";
    const Scenario scenario = load_scenario(file);
    ASSERT_FALSE(scenario.polygons.empty());
    StagedOutput output(file.parent_path() / "out");
    try {
        (void)render_scenario(scenario, load_run_config("pxpl5", {}), output);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "polygons");
        // Written by the registry from the kernels' declared features: the kernels on the machine that can.
        EXPECT_NE(std::string(e.what()).find("the dummy kernel does not scan-convert polygons; use kernel = \"levoy\""),
                  std::string::npos)
            << e.what();
    }
}

TEST(Registry, RefusalsNameTheKernelsWithTheFeature) {
    register_dummy_once();
    const fs::path file = write_scenario("dummy-region", "dummy");
    std::ofstream(file, std::ios::app) << "[region]\nshape = \"box\"\ncenter = [4, 4, 4]\nhalf_size = [2, 2, 2]\n";
    const Scenario scenario = load_scenario(file);
    for (const Kernel* kernel : kernels()) {
        Scenario own = scenario;
        own.kernel = kernel->name();
        own.image.resampling = kernel->name() == "perm" || kernel->name() == "reference"
                                   ? ResamplingOrder::InterpolateThenShade
                                   : ResamplingOrder::ShadeThenInterpolate;
        if (kernel->features().regions) {
            EXPECT_NO_THROW(check_scenario(*kernel, own)) << kernel->name();
            continue;
        }
        try {
            check_scenario(*kernel, own);
            ADD_FAILURE() << kernel->name() << " took a region it declares no tool for";
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), "region") << kernel->name();
            EXPECT_NE(std::string(e.what()).find("has no volume-of-interest tool; use kernel = \"levoy\""),
                      std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace pp5
