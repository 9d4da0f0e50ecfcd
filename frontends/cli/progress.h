#pragma once
// Progress on stderr for runs that take longer than a second; quiet for quick ones.

#include "sim/core/work_progress.h"

#include <chrono>
#include <optional>
#include <string>

namespace pp5::cli {

class Progress {
public:
    Progress(std::string what, std::size_t total);
    void update(std::size_t done);
    void finish();

private:
    using Clock = std::chrono::steady_clock;
    std::string what_;
    std::size_t total_;
    Clock::time_point start_ = Clock::now();
    Clock::time_point last_print_{};
    bool printed_ = false;
};

// Progress of the long stages inside a frame (sim/core/work_progress.h), one Progress per stage.
class StageProgress final : public WorkListener {
public:
    explicit StageProgress(std::string what) : what_(std::move(what)) {}
    void on_work(std::string_view stage, std::size_t done, std::size_t total) override;

private:
    std::string what_;
    std::string stage_;
    std::size_t last_done_ = 0;
    std::optional<Progress> progress_;
};

}  // namespace pp5::cli
