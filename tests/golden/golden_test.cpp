// Golden statistics: every shipped scenario (traces/scenarios) rendered by the pp5sim command, its
// stats.json (host timings removed) and the pixels of every image it writes compared with the files
// recorded under tests/golden/scenarios/. A refactor of the machine or of a kernel must leave them
// identical; a change that moves them on purpose refreshes them in the same commit and says why.
//
// Refresh: PP5_GOLDEN_REFRESH=1 build/tests/golden/test_golden   (writes the files in the source tree)
// PP5SIM=path runs another pp5sim binary (an older build, to record what it gave).

#include "frontends/image_io.h"
#include "tests/support/run_files.h"
#include "tests/support/source_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pp5::read_rgb8;
using pp5::Rgb8Picture;
using pp5::test::read_file;
using pp5::test::without_host_fields;

const fs::path kSource = pp5::test::source_dir();
const fs::path kGolden = kSource / "tests/golden/scenarios";

void write_file(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
}

bool refreshing() {
    const char* flag = std::getenv("PP5_GOLDEN_REFRESH");
    return flag != nullptr && std::string(flag) == "1";
}

// FNV-1a over an image's size and decoded 8-bit pixels: the same picture gives the same digest
// whatever the PNG encoder's choices.
std::string pixel_digest(const fs::path& path) {
    Rgb8Picture picture;
    try {
        picture = read_rgb8(path);
    } catch (const std::runtime_error&) {
        return "unreadable";
    }
    std::uint64_t h = 1469598103934665603ull;
    const auto mix = [&h](std::uint64_t byte) {
        h ^= byte;
        h *= 1099511628211ull;
    };
    for (const int v : {picture.width, picture.height, picture.channels})
        for (int b = 0; b < 4; ++b) mix(static_cast<std::uint64_t>((v >> (8 * b)) & 0xff));
    for (const unsigned char p : picture.bytes) mix(p);
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
}

std::vector<std::string> shipped_scenarios() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kSource / "traces/scenarios"))
        if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, StatisticsAndImagesMatchTheRecordedRun) {
    const std::string name = GetParam();
    const fs::path out = fs::temp_directory_path() / ("pp5_golden_" + name);
    fs::remove_all(out);
    const char* binary = std::getenv("PP5SIM");
    const std::string command = std::string(binary != nullptr ? binary : PP5SIM_BINARY) + " render " + name +
                                " --threads 2 --out " + out.string() + " > " + out.string() + ".log 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << read_file(out.string() + ".log");

    const nlohmann::json stats = without_host_fields(nlohmann::json::parse(read_file(out / "stats.json")));
    nlohmann::json images = nlohmann::json::object();
    for (const auto& entry : fs::directory_iterator(out))
        if (entry.path().extension() == ".png" || entry.path().extension() == ".exr")
            images[entry.path().filename().string()] = pixel_digest(entry.path());

    const fs::path golden = kGolden / name;
    if (refreshing()) {
        write_file(golden / "stats.json", stats.dump(1) + "\n");
        write_file(golden / "images.json", images.dump(1) + "\n");
        GTEST_SKIP() << "refreshed " << golden;
    }
    ASSERT_TRUE(fs::exists(golden / "stats.json"))
        << "no golden files for " << name << "; refresh them (see the file's head)";
    const nlohmann::json expected_stats = nlohmann::json::parse(read_file(golden / "stats.json"));
    const nlohmann::json expected_images = nlohmann::json::parse(read_file(golden / "images.json"));
    // A JSON patch from the golden to this run names every path that moved.
    const nlohmann::json stats_diff = nlohmann::json::diff(expected_stats, stats);
    EXPECT_TRUE(stats_diff.empty()) << name << ": stats.json differs from the golden run:\n"
                                    << stats_diff.dump(1).substr(0, 6000);
    const nlohmann::json image_diff = nlohmann::json::diff(expected_images, images);
    EXPECT_TRUE(image_diff.empty()) << name << ": images differ from the golden run:\n" << image_diff.dump(1);
    if (HasFailure()) std::cout << "this run's output is kept in " << out << "\n";
    else fs::remove_all(out);
}

// The recorded runs hold Levoy's kernel to its oracle: every frame of every shipped scenario it renders
// (regions, capping and polygons included) within 35 dB of the floating-point reference, which leaves
// nothing of the frame out. A refresh cannot lower that unnoticed.
TEST(GoldenFidelity, EveryLevoyFrameIsWithin35DecibelsOfAnOracleThatOmitsNothing) {
    int frames = 0;
    for (const std::string& name : shipped_scenarios()) {
        const fs::path file = kGolden / name / "stats.json";
        if (!fs::exists(file)) continue;
        const nlohmann::json stats = nlohmann::json::parse(read_file(file));
        if (stats["summary"]["kernel"] != "levoy") continue;
        for (const nlohmann::json& frame : stats["frames"]) {
            ASSERT_TRUE(frame.contains("fidelity")) << name;
            const nlohmann::json& fidelity = frame["fidelity"];
            EXPECT_EQ(fidelity["against"].get<std::string>().find("without"), std::string::npos)
                << name << ": " << fidelity["against"];
            if (fidelity["psnr_db"].is_number()) {
                EXPECT_GE(fidelity["psnr_db"].get<double>(), 35.0) << name << " frame " << frame["index"];
            }
            ++frames;
        }
    }
    EXPECT_GE(frames, 20);
}

INSTANTIATE_TEST_SUITE_P(ShippedScenarios, Golden, ::testing::ValuesIn(shipped_scenarios()),
                         [](const ::testing::TestParamInfo<std::string>& scenario) {
                             std::string id = scenario.param;
                             for (char& c : id)
                                 if (c == '-') c = '_';
                             return id;
                         });

}  // namespace
