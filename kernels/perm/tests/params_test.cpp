// Every perm.* parameter changes what PERM computes, stores or takes, and every gp_cost.perm.* cost
// changes the simulated time on the machine it applies to (Pixel-planes 5, or a lone processor for
// what the PPs do there with perm.shading = pp).

#include "calibration/timing_model.h"
#include "kernels/perm/perm_costs.h"
#include "kernels/perm/perm_settings.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario_inputs.h"
#include "sim/timing/frame_engine.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

// Solid material under a light from a fixed direction, depth-cued, seen from outside: every option
// (the reduction among them) has something to act on.
Scenario scene(int size = 40) {
    const auto path =
        std::filesystem::temp_directory_path() / ("pp5sim_perm_params_" + std::to_string(::getpid()) + ".toml");
    std::ofstream(path)
        << "[scenario]\nkernel = \"perm\"\n[dataset]\nphantom = \"head\"\nsize = " << size
        << "\n[classification]\n"
           "kind = \"piecewise-linear\"\npoints = [{ value = 40.0, opacity = 0.0 }, { value = 80.0, opacity = 0.9 }]\n"
           "[shading]\nambient = 0.2\ndiffuse = 0.7\nspecular = 0.2\nlight_direction = [0.3, 0.5, -1]\n"
           "depth_cue = [1.0, 0.5]\n[camera]\nprojection = \"perspective\"\nview_from = [0.3, -1.0, 0.4]\n"
           "up = [0.0, 0.0, 1.0]\n[image]\nwidth = 64\nheight = 64\nresampling = \"interpolate-then-shade\"\n";
    Scenario s = load_scenario(path);
    std::filesystem::remove(path);
    return s;
}

// What a frame computed, stored and took, as one comparable digest.
std::size_t outcome(const Scenario& s, std::vector<std::string> overrides) {
    overrides.push_back("renderer.backing_store_bits=16384");
    const MachineConfig config = load_run_config("pxpl5", overrides);
    Machine machine(config);
    const Volume volume = load_dataset(s);
    auto run = kernel_for(s).start(machine, config, s, volume);
    auto frame = run->record_frame(s.frames.front());
    const FrameTiming timing = time_frame(machine, frame->work);
    nlohmann::json stored = run->run_stats();
    stored["perm"].erase("build");  // this computer's time
    std::string digest = std::to_string(ticks_to_seconds(timing.duration_ps())) + stored.dump();
    for (const glm::vec4& p : frame->pass_images.back().pixels) digest += std::to_string(static_cast<int>(p.r * 4096));
    return std::hash<std::string>{}(digest);
}

TEST(PermParameters, EachChangesWhatIsComputedStoredOrTaken) {
    const Scenario s = scene();
    const std::size_t base = outcome(s, {});
    const std::vector<std::string> changes = {"perm.density_positions=4",
                                              "perm.gradient_positions=3",
                                              "perm.positions=rounded",
                                              "perm.positions=paper",
                                              "perm.qbm=13",
                                              "perm.candidate_rule=paper_origin",
                                              "perm.index_bytes=4",
                                              "perm.residence=gp_memory;gp.memory_bytes=33554432",
                                              "perm.shading=pp",
                                              "perm.tile_pixels=8"};
    for (const std::string& change : changes) {
        std::vector<std::string> set;  // a change may need a companion ("a;b")
        for (std::size_t at = 0, next; at <= change.size(); at = next + 1) {
            next = std::min(change.find(';', at), change.size());
            set.push_back(change.substr(at, next - at));
        }
        EXPECT_NE(outcome(s, set), base) << change;
    }
    // The reduction needs material thick enough to hide cells: the phantom at 96^3, where the opacity
    // threshold also decides which cells count as opaque.
    const Scenario thick = scene(96);
    const std::vector<std::string> coarse = {"perm.gradient_positions=3"};
    const auto reduced = [&](const char* cells, const char* opacity) {
        std::vector<std::string> o = coarse;
        o.push_back(std::string("perm.reduction_cells=") + cells);
        o.push_back(std::string("perm.reduction_opacity=") + opacity);
        return outcome(thick, o);
    };
    EXPECT_NE(reduced("6", "0.6"), reduced("0", "0.6"));
    EXPECT_NE(reduced("6", "0.6"), reduced("6", "0.7"));
    // And the list is complete (positions twice; the reduction's two above).
    EXPECT_EQ(changes.size() - 1 + 2, PermSettings::params().specs().size());
}

TEST(PermParameters, EachCostChangesTheTimeWhereItApplies) {
    const Scenario s = scene();
    const std::vector<std::string> gp_shading = {"renderer.backing_store_bits=16384"};
    const std::vector<std::string> pp_shading = {"renderer.backing_store_bits=16384", "perm.shading=pp"};
    const RecordedScenario gp(s, load_run_config("pxpl5", gp_shading), 1),
        pp(s, load_run_config("pxpl5", pp_shading), 1);
    for (const ParamSpec& spec : perm_cost_params().specs()) {
        const std::string key = "gp_cost.perm." + spec.name;
        bool changed = false;
        // Each recording on Pixel-planes 5 and on a lone processor (where the PPs' passes become
        // per-position classification and shading).
        for (const RecordedScenario* r : {&gp, &pp})
            for (const char* machine : {"pxpl5", "sun4-280"}) {
                const MachineConfig base = load_run_config(machine, r == &gp ? gp_shading : pp_shading);
                MachineConfig doubled = base;
                doubled.set(key, base.real(key) * 2 + 1, "test");
                changed |= r->time_on(base).front().duration_ps() != r->time_on(doubled).front().duration_ps();
            }
        EXPECT_TRUE(changed) << key;
    }
}

}  // namespace
}  // namespace pp5
