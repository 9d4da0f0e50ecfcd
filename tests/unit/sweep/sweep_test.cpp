// Sweeps: the file's grid and points in the order written, every malformed file refused naming the
// file and the field, shards that cover every point once, results that do not depend on the thread
// or shard count (merged shards are the whole sweep's bytes), and a point that fails recorded as a
// row while the rest run.

#include "frontends/sweep/sweep_run.h"
#include "frontends/sweep/sweep_spec.h"
#include "frontends/sweep/sweep_tables.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

namespace pp5 {
namespace {

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() / ("pp5sim_sweep_" + std::to_string(::getpid()) + "_" + name + ".toml");
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
    EXPECT_EQ(plan[1].parameters, (SweepAssignment{{"ring.clock_mhz", "10"}, {"gp.count", "8"}}));  // first axis slowest
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
        {"[sweep]\nscenarios = [\"head-phantom\"]\nset = [\"gp.count=8\"]\n[vary]\n\"gp.count\" = [4]\n", "vary.gp.count"},
        {std::string(kHead) + "plot_x = \"ring.clock_mhz\"\n[vary]\n\"gp.count\" = [4]\n", "sweep.plot_x"},
        {std::string(kHead) + "uncertainty = 1\n[vary]\n\"gp.count\" = [4]\n", "sweep.uncertainty"},
        {std::string(kHead) + "[vary]\n\"gp.count\" = [1,2,3,4,5,6,7,8,9,10,11]\n\"gp.ray_contexts\" = [1,2,3,4,5,6,7,8,9,10]\n"
                              "\"gp.clock_mhz\" = [1,2,3,4,5,6,7,8,9,10]\n\"ring.channels\" = [1,2,3,4,5,6,7,8,9,10]\n"
                              "\"ring.clock_mhz\" = [1,2,3,4,5,6,7,8,9,10]\n",
         "vary"},
        {std::string(kHead) + "[[points]]\n\"gp.count\" = 4\n\"gp.count\" = 8\n", ""},  // TOML itself refuses a key twice
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
    for (const char* bad : {"5/5", "1", "a/2", "-1/2", "1/0", "1/2/3"}) EXPECT_THROW(parse_shard(bad), InputError) << bad;

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

TEST(SweepRun, ShardsMergeIntoTheWholeSweepAndThreadsChangeNothing) {
    const SweepSpec spec = small_sweep();
    const auto whole_at = [&](std::size_t threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return sweep_to_json(run_sweep(spec, Shard{})).dump();
    };
    const std::string one = whole_at(1), two = whole_at(2);
    EXPECT_EQ(one, two);
    std::vector<std::pair<std::string, nlohmann::json>> shards;
    for (std::size_t k = 0; k < 3; ++k) {
        const Shard shard{k, 3};
        shards.emplace_back(shard_file_name(shard), nlohmann::json::parse(sweep_to_json(run_sweep(spec, shard), shard).dump()));
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

}  // namespace
}  // namespace pp5
