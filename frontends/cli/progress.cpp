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
                                 ? fmt::format(", about {:.0f} s left", elapsed * static_cast<double>(total_ - done) / static_cast<double>(done))
                                 : std::string();
    fmt::print(stderr, "{}: {}/{} ({:.0f}%), {:.1f} s{}\n", what_, done, total_,
               100.0 * static_cast<double>(done) / static_cast<double>(total_), elapsed, left);
    std::fflush(stderr);
    printed_ = true;
    last_print_ = now;
}

void Progress::finish() { update(total_); }

}  // namespace pp5::cli
