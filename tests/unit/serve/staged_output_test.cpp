#include "frontends/staged_output.h"
#include "sim/core/input_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("pp5_staged_output_" + name);
    fs::remove_all(dir);
    return dir;
}

std::size_t files_under(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) n += entry.is_regular_file() ? 1 : 0;
    return n;
}

// Images go to temporary files as they are added, so a long run holds none of its frames' pictures;
// nothing appears under its own name before the commit.
TEST(StagedOutput, ImagesAreWrittenAheadAsTemporariesAndAppearOnlyAtTheCommit) {
    const fs::path out = fresh("commit") / "run";
    StagedOutput output(out);
    output.add_image("frame_0000.png", Image(8, 4), ImageFormat::Png);
    output.add_image("images/frame_0001.png", Image(8, 4), ImageFormat::Png);
    output.add_text("stats.json", "{}\n");
    EXPECT_FALSE(fs::exists(out / "frame_0000.png"));
    EXPECT_EQ(files_under(out), 2u);  // the two images' temporaries, not yet the text
    const auto written = output.commit();
    EXPECT_EQ(written.size(), 3u);
    EXPECT_TRUE(fs::exists(out / "frame_0000.png"));
    EXPECT_TRUE(fs::exists(out / "images/frame_0001.png"));
    for (const auto& entry : fs::recursive_directory_iterator(out))
        EXPECT_FALSE(entry.path().filename().string().starts_with(".partial-")) << entry.path();
}

// A run that stops before its commit (an error in a later frame) leaves nothing: not its temporaries,
// not the folders it made for them; a folder that was there before stays.
TEST(StagedOutput, ARunAbandonedBeforeItsCommitLeavesNothingBehind) {
    const fs::path root = fresh("abandoned");
    fs::create_directories(root);
    std::ofstream(root / "someone_elses.txt") << "kept";
    {
        StagedOutput output(root / "new" / "run");
        output.add_image("images/frame_0000.png", Image(8, 4), ImageFormat::Png);
        EXPECT_TRUE(fs::exists(root / "new" / "run" / "images"));
    }
    EXPECT_FALSE(fs::exists(root / "new"));
    EXPECT_TRUE(fs::exists(root / "someone_elses.txt"));
    {
        StagedOutput output(root);
        output.add_image("frame_0000.png", Image(8, 4), ImageFormat::Png);
    }
    EXPECT_EQ(files_under(root), 1u);
    EXPECT_TRUE(fs::exists(root));
}

}  // namespace
}  // namespace pp5
