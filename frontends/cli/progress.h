#pragma once
// Progress on stderr for runs that take longer than a second; quiet for quick ones.

#include <chrono>
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

}  // namespace pp5::cli
