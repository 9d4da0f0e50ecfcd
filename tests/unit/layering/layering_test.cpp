// Layers only point down: every project include in sim/, ring/, scene/, kernels/, calibration/ and frontends/
// names a file of its own folder or of a lower layer. Kernels do not include one another, the ring
// depends on the event core alone, the machine (sim/, ring/) includes no kernel, and the machine and
// the scene (scene/) include nothing of each other but the event core.

#include "tests/support/source_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// Folders and their layers, lowest first. A file may include from its own folder or from a folder of
// a lower layer; folders of one layer may not include each other. Any other folder under kernels/ is
// a kernel.
struct Layer {
    const char* folder;
    int rank;
};
constexpr Layer kLayers[] = {
    {"sim/core", 0},
    {"ring", 1},
    {"sim/pixel_processors", 1},
    {"scene/volume", 1},
    {"scene/render", 1},
    {"sim/components", 2},
    {"scene/reference", 2},
    {"sim/machine", 3},
    {"scene/scenario", 3},
    {"sim/timing", 4},
    {"kernels/api", 5},
    {"kernels/shared/pp_volume", 5},
    {"kernels/shared/screen_regions", 5},
    {"kernels/registry", 7},
    {"calibration", 8},
    {"frontends", 9},
};
constexpr int kKernelRank = 6;

struct Place {
    std::string folder;
    int rank = -1;  // -1: not a project folder
};

// A kernel's tests (kernels/<kernel>/tests/) live beside it but sit above every layer, as tests/ does.
bool is_test_code(const std::string& path) { return path.find("/tests/") != std::string::npos; }

Place place_of(const std::string& path) {
    Place best;
    if (is_test_code(path)) return best;
    for (const Layer& layer : kLayers) {
        const std::string folder = layer.folder;
        if (path.rfind(folder + "/", 0) == 0 && folder.size() > best.folder.size()) best = Place{folder, layer.rank};
    }
    if (best.rank < 0 && path.rfind("kernels/", 0) == 0) {
        const auto slash = path.find('/', 8);
        if (slash != std::string::npos) best = Place{path.substr(0, slash), kKernelRank};
    }
    return best;
}

struct Include {
    std::string file;      // relative to the source tree
    std::string included;  // as written
};

// The two sides of the lower layers: the machine (sim/, ring/) and what it renders (scene/). Neither
// includes the other, but for the event core under both.
bool is_machine(const std::string& folder) { return folder.rfind("sim/", 0) == 0 || folder == "ring"; }
bool is_scene(const std::string& folder) { return folder.rfind("scene/", 0) == 0; }

// Every violation as "file includes header: why".
std::vector<std::string> violations(const std::vector<Include>& includes) {
    std::vector<std::string> out;
    for (const Include& inc : includes) {
        const Place from = place_of(inc.file);
        const Place to = place_of(inc.included);
        if (from.rank < 0 || to.rank < 0 || from.folder == to.folder) continue;
        if (to.rank >= from.rank)
            out.push_back(inc.file + " includes " + inc.included + ": " + to.folder + " is not below " + from.folder);
        else if (is_machine(from.folder) && is_scene(to.folder))
            out.push_back(inc.file + " includes " + inc.included + ": the machine knows no scene");
        else if (is_scene(from.folder) && is_machine(to.folder) && to.folder != "sim/core")
            out.push_back(inc.file + " includes " + inc.included + ": the scene rests on sim/core alone");
    }
    return out;
}

// The header a `#include "..."` line names, or empty. (Plain string work: <regex> sets off false
// maybe-uninitialized warnings in libstdc++ 12 under the sanitizers.)
std::string quoted_include(const std::string& line) {
    std::size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line[i] != '#') return {};
    i = line.find_first_not_of(" \t", i + 1);
    if (i == std::string::npos || line.compare(i, 7, "include") != 0) return {};
    i = line.find_first_not_of(" \t", i + 7);
    if (i == std::string::npos || line[i] != '"') return {};
    const std::size_t end = line.find('"', i + 1);
    return end == std::string::npos ? std::string() : line.substr(i + 1, end - i - 1);
}

std::vector<Include> project_includes() {
    const fs::path root = pp5::test::source_dir();
    std::vector<Include> all;
    for (const char* top : {"sim", "ring", "scene", "kernels", "calibration", "frontends"}) {
        for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
            const std::string ext = entry.path().extension().string();
            if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
            const std::string file = fs::relative(entry.path(), root).generic_string();
            std::ifstream in(entry.path());
            std::string line;
            while (std::getline(in, line))
                if (std::string header = quoted_include(line); !header.empty())
                    all.push_back(Include{file, std::move(header)});
        }
    }
    return all;
}

TEST(Layering, EveryIncludePointsDown) {
    const std::vector<Include> includes = project_includes();
    ASSERT_GT(includes.size(), 300u);  // the scan found the tree
    std::string report;
    for (const std::string& v : violations(includes)) report += v + "\n";
    EXPECT_TRUE(report.empty()) << report;
}

TEST(Layering, TheCheckCatchesWhatItForbids) {
    const std::vector<std::string> found = violations({
        {"sim/components/renderer.cpp", "kernels/shared/pp_volume/pp_shading.h"},  // the machine naming a kernel
        {"ring/ring_network.cpp", "sim/components/renderer.h"},                    // the ring above the event core
        {"kernels/levoy/ray_caster.cpp", "kernels/yuan/splat.h"},                  // a kernel including another
        {"calibration/fit.cpp", "frontends/plot.h"},                               // calibration above the frontends
        {"frontends/cli/main.cpp", "calibration/fit.h"},                           // fine
        {"kernels/levoy/ray_caster.cpp", "scene/reference/trilinear.h"},           // fine: shared maths
        {"sim/timing/frame_engine.cpp", "sim/timing/frame_engine.h"},              // fine: its own folder
        {"sim/timing/frame_engine.cpp", "scene/volume/volume.h"},                  // the machine naming the scene
        {"scene/reference/composite.cpp", "sim/pixel_processors/pp_array.h"},      // the scene naming the machine
        {"scene/volume/volume.cpp", "sim/core/input_error.h"},                     // fine: the event core
        {"kernels/yuan/tests/splatter_test.cpp", "frontends/render_scenario.h"},   // fine: a kernel's tests
    });
    EXPECT_EQ(found.size(), 6u) << ::testing::PrintToString(found);
}

}  // namespace
