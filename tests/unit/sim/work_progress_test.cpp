#include "sim/core/work_progress.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace pp5 {
namespace {

struct WorkRecorder final : WorkListener {
    std::vector<std::pair<std::string, std::size_t>> heard;
    void on_work(std::string_view stage, std::size_t done, std::size_t) override {
        heard.emplace_back(std::string(stage), done);
    }
};

TEST(WorkProgress, ReachesTheListenerOfTheCallingThreadWhileItIsInstalled) {
    WorkRecorder outer;
    WorkRecorder inner;
    report_work("before", 1, 3);  // nobody listening: nothing happens
    {
        const ScopedWorkListener listening(outer);
        report_work("stage", 1, 3);
        {
            const ScopedWorkListener nested(inner);
            report_work("stage", 2, 3);
        }
        report_work("stage", 3, 3);
        // Another thread has its own (no) listener: a sweep's points do not report into this one.
        std::thread([] { report_work("elsewhere", 1, 1); }).join();
    }
    report_work("after", 1, 1);
    const std::vector<std::pair<std::string, std::size_t>> expected_outer{{"stage", 1}, {"stage", 3}};
    EXPECT_EQ(outer.heard, expected_outer);
    const std::vector<std::pair<std::string, std::size_t>> expected_inner{{"stage", 2}};
    EXPECT_EQ(inner.heard, expected_inner);
}

}  // namespace
}  // namespace pp5
