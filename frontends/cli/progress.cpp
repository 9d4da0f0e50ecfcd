#include "frontends/cli/progress.h"

#include <fmt/core.h>

#include <cstdio>
#include <string>

namespace pp5::cli {

Progress::Progress(std::string what, std::size_t total) : what_(std::move(what)), total_(total) {}

void Progress::update(std::size_t done) {
    const auto now = Clock::now();
    if (now - start_ < std::chrono::seconds(1)) return;
    if (printed_ && now - last_print_ < std::chrono::milliseconds(500) && done != total_) return;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    // The time left, from the pace so far, once something is done.
    const std::string left = done > 0 && done < total_
                                 ? fmt::format(", about {:.0f} s left",
                                               elapsed * static_cast<double>(total_ - done) / static_cast<double>(done))
                                 : std::string();
    fmt::print(stderr, "{}: {}/{} ({:.0f}%), {:.1f} s{}\n", what_, done, total_,
               100.0 * static_cast<double>(done) / static_cast<double>(total_), elapsed, left);
    std::fflush(stderr);
    printed_ = true;
    last_print_ = now;
}

void Progress::finish() { update(total_); }

void StageProgress::on_work(std::string_view stage, std::size_t done, std::size_t total) {
    // A new stage, or the same one starting again in the next frame.
    if (!progress_ || stage != stage_ || done <= last_done_) {
        stage_ = std::string(stage);
        progress_.emplace(what_ + ": " + stage_, total);
    }
    last_done_ = done;
    progress_->update(done);
}

}  // namespace pp5::cli
