// Sweeps: the file's grid and points in the order written, every malformed file refused naming the
// file and the field, shards that cover every point once, results that do not depend on the thread
// or shard count (merged shards are the whole sweep's bytes), and a point that fails recorded as a
// row while the rest run.

#include "frontends/render_session.h"
#include "frontends/sweep/sweep_run.h"
#include "frontends/sweep/sweep_spec.h"
#include "frontends/sweep/sweep_tables.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

namespace pp5 {
namespace {

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path =
        std::filesystem::temp_directory_path() / ("pp5sim_sweep_" + std::to_string(::getpid()) + "_" + name + ".toml");
    std::ofstream(path) << text;
    return path;
}

const char* kHead = "[sweep]\nname = \"t\"\nscenarios = [\"head-phantom\"]\nframes = 1\n";

TEST(SweepFile, AxesKeepTheFilesOrderAndPointsFollowTheGrid) {
    const auto path = write("good", std::string(kHead) + "uncertainty = true\n" +
                                        "[vary]\n\"ring.clock_mhz\" = [10.0, 20.0]\ngp.count = [4, 8, 16]\n"
                                        "[[points]]\n\"gp.count\" = 64\nlevoy.ray_assignment = \"work_queue\"\n");
    const SweepSpec spec = load_sweep_file(path);
    std::filesystem::remove(path);
    EXPECT_TRUE(spec.uncertainty);
    ASSERT_EQ(spec.axes.size(), 2u);
    EXPECT_EQ(spec.axes[0].key, "ring.clock_mhz");  // as written, though "gp" sorts first
    EXPECT_EQ(spec.axes[1].key, "gp.count");
    EXPECT_EQ(spec.axes[0].values, (std::vector<std::string>{"10", "20"}));
    const std::vector<SweepPoint> plan = plan_sweep(spec);
    ASSERT_EQ(plan.size(), 7u);
    EXPECT_EQ(plan[1].parameters,
              (SweepAssignment{{"ring.clock_mhz", "10"}, {"gp.count", "8"}}));  // first axis slowest
    EXPECT_EQ(plan[3].parameters, (SweepAssignment{{"ring.clock_mhz", "20"}, {"gp.count", "4"}}));
    EXPECT_EQ(plan[6].parameters, (SweepAssignment{{"gp.count", "64"}, {"levoy.ray_assignment", "work_queue"}}));
}

TEST(SweepFile, MalformedFilesAreRefusedNamingTheField) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"[sweep]\nscenarios = [\"head-phantom\"]\n[vary]\n\"gp.count\" = [4]\n[extra]\n", "extra"},
        {"[vary]\n\"gp.count\" = [4]\n", "sweep"},
        {std::string(kHead) + "colour = 3\n[vary]\n\"gp.count\" = [4]\n", "sweep.colour"},
        {std::string(kHead) + "[vary]\n\"gp.count\" = 4\n", "vary.gp.count"},
        {std::string(kHead) + "[vary]\n\"gp.count\" = []\n", "vary.gp.count"},
        {std::string(kHead) + "[vary]\n\"gp.count\" = [4, 4]\n", "vary.gp.count[1]"},
        {std::string(kHead) + "[vary]\n\"gp.cont\" = [4]\n", "vary.gp.cont[0]"},
        {std::string(kHead) + "[vary]\n\"gp.count\" = [0]\n", "vary.gp.count[0]"},
        {std::string(kHead) + "[vary]\n\"gp.count\" = [[1]]\n", "vary.gp.count[0]"},
        {std::string(kHead) + "[vary]\na.b.c.d.e.f.g.h.i.j = [1]\n", "vary.a.b.c.d.e.f.g.h.i"},
        {"[sweep]\nscenarios = [\"no-such-scenario\"]\n[vary]\n\"gp.count\" = [4]\n", "sweep.scenarios[0]"},
        {"[sweep]\nscenarios = [\"head-phantom\"]\nset = [\"gp.count=8\"]\n[vary]\n\"gp.count\" = [4]\n",
         "vary.gp.count"},
        {std::string(kHead) + "plot_x = \"ring.clock_mhz\"\n[vary]\n\"gp.count\" = [4]\n", "sweep.plot_x"},
        {std::string(kHead) + "uncertainty = 1\n[vary]\n\"gp.count\" = [4]\n", "sweep.uncertainty"},
        // Over the point cap: refused as such before any value is checked (0 GPs would be refused too).
        {std::string(kHead) +
             "[vary]\n\"gp.count\" = [0,2,3,4,5,6,7,8,9,10,11]\n\"gp.ray_contexts\" = [1,2,3,4,5,6,7,8,9,10]\n"
             "\"gp.clock_mhz\" = [1,2,3,4,5,6,7,8,9,10]\n\"ring.channels\" = [1,2,3,4,5,6,7,8,9,10]\n"
             "\"ring.clock_mhz\" = [1,2,3,4,5,6,7,8,9,10]\n",
         "vary"},
        {std::string(kHead) + "[[points]]\n\"gp.count\" = 4\n\"gp.count\" = 8\n",
         ""},  // TOML itself refuses a key twice
        // The name becomes out/sweeps/<name>: nothing that climbs out of it.
        {"[sweep]\nname = \"../../elsewhere\"\nscenarios = [\"head-phantom\"]\n[vary]\n\"gp.count\" = [4]\n",
         "sweep.name"},
        {"[sweep]\nname = \"/tmp/x\"\nscenarios = [\"head-phantom\"]\n[vary]\n\"gp.count\" = [4]\n", "sweep.name"},
        {"[sweep]\nname = \"..\"\nscenarios = [\"head-phantom\"]\n[vary]\n\"gp.count\" = [4]\n", "sweep.name"},
        // Rows and plots are known by the scenario's name: the same scenario twice is refused.
        {"[sweep]\nscenarios = [\"head-phantom\", \"head-phantom\"]\n[vary]\n\"gp.count\" = [4]\n",
         "sweep.scenarios[1]"},
    };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const auto path = write("bad" + std::to_string(i), cases[i].first);
        try {
            load_sweep_file(path);
            ADD_FAILURE() << "accepted:\n" << cases[i].first;
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), path.string()) << e.what();
            if (!cases[i].second.empty()) {
                EXPECT_EQ(e.field(), cases[i].second) << e.what();
            }
        }
        std::filesystem::remove(path);
    }
}

TEST(SweepShards, EveryPointRunsInExactlyOneShardAndTheLaunchersSayWhich) {
    for (std::size_t n = 1; n <= 5; ++n) {
        std::multiset<std::size_t> taken;
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t p = 0; p < 23; ++p)
                if (Shard{k, n}.takes(p)) taken.insert(p);
        EXPECT_EQ(taken.size(), 23u);
        EXPECT_EQ(std::set<std::size_t>(taken.begin(), taken.end()).size(), 23u);
    }
    EXPECT_EQ(parse_shard("2/5").index, 2u);
    for (const char* bad : {"5/5", "1", "a/2", "-1/2", "1/0", "1/2/3"})
        EXPECT_THROW(parse_shard(bad), InputError) << bad;

    ::setenv("OMPI_COMM_WORLD_RANK", "1", 1);
    ::setenv("OMPI_COMM_WORLD_SIZE", "3", 1);
    auto s = shard_from_environment();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 1u);
    EXPECT_EQ(s->count, 3u);
    ::setenv("OMPI_COMM_WORLD_RANK", "3", 1);
    EXPECT_THROW(shard_from_environment(), InputError);
    ::unsetenv("OMPI_COMM_WORLD_RANK");
    ::unsetenv("OMPI_COMM_WORLD_SIZE");
    // A Slurm array numbered from 1 (--array=1-4).
    ::setenv("SLURM_ARRAY_TASK_ID", "3", 1);
    ::setenv("SLURM_ARRAY_TASK_MIN", "1", 1);
    ::setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
    s = shard_from_environment();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 2u);
    EXPECT_EQ(s->count, 4u);
    for (const char* v : {"SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_COUNT"}) ::unsetenv(v);
    EXPECT_FALSE(shard_from_environment());
}

// A shard as another machine would write it: shard 0 of 2 of a sweep of two scenarios over two GP
// counts (points 0 and 2 are its share), with the names "a b" and "a_b" that a plot's file name
// would make the same.
nlohmann::json hand_written_shard(std::size_t index) {
    nlohmann::json shard = nlohmann::json::parse(R"({
      "sweep": {"name": "t", "description": "", "scenarios": ["a b", "a_b"], "machine": "pxpl5", "set": [],
                "frames": 1, "axes": [{"key": "gp.count", "values": ["4", "8"]}], "points": [],
                "total_points": 4, "plot_x": "", "plot_metric": "frame_ms",
                "kernels": {"a b": "levoy", "a_b": "levoy"}},
      "columns": [{"name": "frame_ms", "unit": "ms", "description": "simulated frame time"}],
      "results": []})");
    for (std::size_t point = index; point < 4; point += 2) {
        const std::string gps = point % 2 == 0 ? "4" : "8";
        shard["results"].push_back(
            {{"index", point},
             {"scenario", point < 2 ? "a b" : "a_b"},
             {"varied", {{"gp.count", gps}}},
             {"frames",
              {{{"frame", 0}, {"label", "f"}, {"metrics", {{"frame_ms", 10.0 + static_cast<double>(point)}}}}}},
             {"parameters", {{"gp.count", std::stoi(gps)}}}});
    }
    shard["shard"] = {{"index", index}, {"count", 2}};
    return shard;
}

TEST(SweepShards, MalformedShardsAreRefusedNamingTheFileAndTheField) {
    const auto shards_with = [](const std::function<void(nlohmann::json&)>& change) {
        std::vector<std::pair<std::string, nlohmann::json>> shards{{"s0.json", hand_written_shard(0)},
                                                                   {"s1.json", hand_written_shard(1)}};
        change(shards[0].second);
        return shards;
    };
    const SweepResult merged = merge_sweep_shards(shards_with([](nlohmann::json&) {}));
    ASSERT_EQ(merged.points.size(), 4u);
    EXPECT_EQ(merged.points[3].frames[0].values[0], 13.0);
    // Two scenarios whose plot names would clash get a plot each.
    const auto plots = sweep_plots(merged);
    ASSERT_EQ(plots.size(), 2u);
    EXPECT_EQ(plots[0].first, "sweep_a_b");
    EXPECT_EQ(plots[1].first, "sweep_a_b_2");

    using Change = std::function<void(nlohmann::json&)>;
    const std::vector<std::pair<Change, std::string>> cases = {
        {[](auto& j) { j["shard"]["index"] = "0"; }, "shard.index"},
        {[](auto& j) { j["shard"]["index"] = nullptr; }, "shard.index"},
        {[](auto& j) { j["shard"]["index"] = 1.5; }, "shard.index"},
        {[](auto& j) { j["shard"]["index"] = -1; }, "shard.index"},
        {[](auto& j) { j["shard"]["index"] = 2; }, "shard.index"},
        {[](auto& j) { j["shard"]["count"] = 0; }, "shard.count"},
        {[](auto& j) { j["shard"] = 3; }, "shard"},
        {[](auto& j) { j.erase("shard"); }, "shard"},
        {[](auto& j) { j = nlohmann::json::array(); }, "sweep"},
        {[](auto& j) { j["sweep"] = "x"; }, "sweep"},
        {[](auto& j) { j["sweep"].erase("axes"); }, "sweep.axes"},
        {[](auto& j) {
             j["sweep"]["axes"][0]["values"] = {4, 8};
         },
         "sweep.axes[0].values[0]"},
        {[](auto& j) { j["sweep"]["axes"][0]["values"] = nlohmann::json::array(); }, "sweep.axes[0].values"},
        {[](auto& j) { j["sweep"]["axes"][0] = "gp.count"; }, "sweep.axes[0]"},
        {[](auto& j) { j["sweep"]["total_points"] = 5; }, "sweep.total_points"},
        {[](auto& j) { j["sweep"]["scenarios"] = nlohmann::json::array(); }, "sweep.scenarios"},
        {[](auto& j) { j["sweep"]["kernels"]["a b"] = 1; }, "sweep.kernels.a b"},
        {[](auto& j) { j["sweep"]["points"] = {1}; }, "sweep.points[0]"},
        {[](auto& j) { j["columns"][0].erase("unit"); }, "columns[0].unit"},
        {[](auto& j) { j["columns"].push_back(j["columns"][0]); }, "columns[1].name"},
        {[](auto& j) { j["results"][0]["index"] = 9; }, "results[0].index"},
        {[](auto& j) { j["results"][0]["scenario"] = "c"; }, "results[0].scenario"},
        {[](auto& j) { j["results"][0]["varied"]["gp.count"] = 4; }, "results[0].varied.gp.count"},
        {[](auto& j) { j["results"][0]["frames"][0]["metrics"]["frame_ms"] = "fast"; },
         "results[0].frames[0].metrics.frame_ms"},
        {[](auto& j) { j["results"][0]["frames"][0]["metrics"].erase("frame_ms"); },
         "results[0].frames[0].metrics.frame_ms"},
        {[](auto& j) { j["results"][0]["frames"][0]["frame"] = -3; }, "results[0].frames[0].frame"},
        {[](auto& j) { j["results"][0]["error"] = 7; }, "results[0].error"},
        {[](auto& j) { j["results"][1]["index"] = 1; }, "results"},  // point 1 is shard 1's
    };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        try {
            merge_sweep_shards(shards_with(cases[i].first));
            ADD_FAILURE() << "case " << i << " accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), "s0.json") << "case " << i << ": " << e.what();
            EXPECT_EQ(e.field(), cases[i].second) << "case " << i << ": " << e.what();
        }
    }
}

SweepSpec small_sweep() {
    SweepSpec spec;
    spec.file = "test";
    spec.name = "small";
    spec.scenarios = {"head-phantom"};
    spec.frames = 2;
    spec.axes = {{"gp.count", {"4", "16"}}, {"levoy.ray_assignment", {"interleaved_tiles", "work_queue"}}};
    spec.points = {{{"gp.memory_bytes", "2048"}}};  // too small for the cache: this point fails
    check_sweep_spec(spec);
    return spec;
}

// Two tests, so that ThreadSanitizer (.ci/tsan), which runs the tests named for threads, runs only
// the two whole sweeps and not the shards as well.
TEST(SweepRun, ThreadsChangeNothing) {
    const SweepSpec spec = small_sweep();
    const auto whole_at = [&](std::size_t threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return sweep_to_json(run_sweep(spec, Shard{})).dump();
    };
    EXPECT_EQ(whole_at(1), whole_at(2));
}

TEST(SweepRun, ShardsMergeIntoTheWholeSweep) {
    const SweepSpec spec = small_sweep();
    const std::string one = sweep_to_json(run_sweep(spec, Shard{})).dump();
    std::vector<std::pair<std::string, nlohmann::json>> shards;
    for (std::size_t k = 0; k < 3; ++k) {
        const Shard shard{k, 3};
        shards.emplace_back(shard_file_name(shard),
                            nlohmann::json::parse(sweep_to_json(run_sweep(spec, shard), shard).dump()));
    }
    const SweepResult merged = merge_sweep_shards(shards);
    EXPECT_EQ(sweep_to_json(merged).dump(), nlohmann::json::parse(one).dump());
    const SweepResult whole = sweep_from_json(nlohmann::json::parse(one), "whole");
    EXPECT_EQ(sweep_to_csv(merged), sweep_to_csv(whole));

    // More GPs take less time; the failed point says why and the others ran.
    ASSERT_EQ(whole.points.size(), 5u);
    EXPECT_LT(whole.points[2].frames[0].values[0].value(), whole.points[0].frames[0].values[0].value());
    EXPECT_NE(whole.points[4].error.find("gp.memory_bytes"), std::string::npos) << whole.points[4].error;
    EXPECT_TRUE(whole.points[4].frames.empty());
    EXPECT_EQ(whole.points[4].parameters["gp.memory_bytes"], 2048);
    EXPECT_NE(sweep_to_csv(whole).find("error: "), std::string::npos);

    // A shard missing, a shard twice, or a shard of another sweep is refused.
    auto missing = shards;
    missing.pop_back();
    EXPECT_THROW(merge_sweep_shards(missing), InputError);
    auto twice = shards;
    twice.back() = twice.front();
    EXPECT_THROW(merge_sweep_shards(twice), InputError);
    auto other = shards;
    other[1].second["sweep"]["name"] = "another";
    EXPECT_THROW(merge_sweep_shards(other), InputError);
}

TEST(SweepRun, PointsThatOnlyRetimeMatchAFreshRecordingOnTheirMachine) {
    SweepSpec spec = small_sweep();
    spec.points.clear();
    spec.axes = {{"gp.count", {"4", "16"}}};
    const SweepResult swept = run_sweep(spec, Shard{});
    // The same point alone, fixed (so recorded on its own machine, not re-timed from the default's).
    spec.axes.clear();
    spec.fixed = {"gp.count=16"};
    spec.points = {{}};
    const SweepResult alone = run_sweep(spec, Shard{});
    ASSERT_EQ(alone.points.size(), 1u);
    for (std::size_t f = 0; f < 2; ++f) EXPECT_EQ(swept.points[1].frames[f].values, alone.points[0].frames[f].values);
}

// One book for utilisation: a sweep point's GP and ring utilisation are the ones stats.json reports for
// the same frame on the same machine (the components' busy time over the frame, every phase).
TEST(SweepRun, UtilisationIsTheOneARenderReports) {
    SweepSpec spec = small_sweep();
    spec.axes.clear();
    spec.fixed = {"gp.count=8"};
    spec.points = {{}};
    spec.frames = 1;
    const SweepResult swept = run_sweep(spec, Shard{});
    ASSERT_EQ(swept.points.size(), 1u);
    const auto column = [&](const std::string& name) {
        for (std::size_t c = 0; c < swept.columns.size(); ++c)
            if (swept.columns[c].name == name) return swept.points[0].frames[0].values[c].value();
        ADD_FAILURE() << "no column " << name;
        return -1.0;
    };
    const Scenario scenario = load_scenario(resolve_scenario_file("head-phantom"));
    RenderSession session(scenario, load_run_config("pxpl5", {"gp.count=8"}), nullptr, "png", false);
    const SessionFrame frame = session.render(scenario.frames.front());
    EXPECT_GT(frame.timing.activity.gps, 0.0);
    EXPECT_EQ(column("gp_utilisation"), frame.timing.activity.gps);
    EXPECT_EQ(column("ring_utilisation"), frame.timing.activity.ring);
}

// The kernel as an axis: every point is rendered by its kernel (its metrics in its rows, the kernel in
// its parameters and the CSV), a kernel that cannot render the scenario is a row saying why, the Levoy
// points are those of the same sweep without the axis, and an unknown kernel is refused up front.
TEST(SweepRun, AKernelAxisRendersEachPointWithItsKernel) {
    SweepSpec spec = small_sweep();
    spec.frames = 1;
    spec.points.clear();
    spec.axes = {{"kernel", {"levoy", "yuan", "wilson", "perm"}}, {"gp.count", {"4", "16"}}};
    check_sweep_spec(spec);
    const SweepResult swept = run_sweep(spec, Shard{});
    ASSERT_EQ(swept.points.size(), 8u);
    const auto column = [&](const std::string& name) {
        for (std::size_t c = 0; c < swept.columns.size(); ++c)
            if (swept.columns[c].name == name) return c;
        throw std::runtime_error("no column " + name);
    };
    std::size_t rendered = 0;
    for (std::size_t k = 0; k < 4; ++k) {
        const SweepPointResult& few = swept.points[2 * k];
        const SweepPointResult& many = swept.points[2 * k + 1];
        const std::string kernel = spec.axes[0].values[k];
        EXPECT_EQ(few.parameters["kernel"], kernel);
        EXPECT_EQ(many.parameters["kernel"], kernel);
        if (!few.error.empty()) {
            EXPECT_EQ(few.error, many.error);  // the kernel refuses the scenario, on any machine
            continue;
        }
        ++rendered;
        ASSERT_EQ(few.frames.size(), 1u);
        const double slow = few.frames[0].values[column("simulated_seconds")].value(),
                     fast = many.frames[0].values[column("simulated_seconds")].value();
        EXPECT_GT(slow, fast) << kernel << ": 4 GPs against 16";
        // The kernel's own first metric is in its rows.
        const Kernel* k_ = find_kernel(kernel);
        ASSERT_NE(k_, nullptr);
        if (!k_->metrics().empty()) {
            EXPECT_TRUE(few.frames[0].values[column(k_->metrics().front().name)].has_value()) << kernel;
        }
    }
    EXPECT_GE(rendered, 2u);
    EXPECT_TRUE(swept.points[0].error.empty()) << swept.points[0].error;  // Levoy's own scenario
    EXPECT_NE(sweep_to_csv(swept).find("point,scenario,kernel,gp.count"), std::string::npos);

    SweepSpec levoy_only = spec;
    levoy_only.axes = {{"gp.count", {"4", "16"}}};
    const SweepResult alone = run_sweep(levoy_only, Shard{});
    for (std::size_t p = 0; p < 2; ++p)
        for (std::size_t c = 0; c < alone.columns.size(); ++c)
            EXPECT_EQ(swept.points[p].frames[0].values[column(alone.columns[c].name)],
                      alone.points[p].frames[0].values[c]);

    spec.axes[0].values[1] = "yaun";
    try {
        check_sweep_spec(spec);
        ADD_FAILURE() << "an unknown kernel was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "vary.kernel[1]");
        EXPECT_NE(e.reason().find("levoy"), std::string::npos) << e.reason();
    }
}

}  // namespace
}  // namespace pp5
