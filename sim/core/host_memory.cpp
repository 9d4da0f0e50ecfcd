#include "sim/core/host_memory.h"

#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <exception>
#include <fstream>
#include <optional>
#include <string_view>
#include <utility>

namespace pp5 {

namespace {

// A limit file's number of bytes; none for "max", a missing file, or anything unreadable.
std::optional<double> read_limit_bytes(const std::string& path) {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text) || text == "max") return std::nullopt;
    unsigned long long value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return static_cast<double>(value);
}

// The tightest limit on the way from this process's group up to the root: each ancestor's limit binds
// its descendants too. In a container the group is "/", whose limit is the container's.
void take_tightest_on_path(const std::string& mount, std::string path, const char* limit_file,
                           std::optional<double>& tightest) {
    while (true) {
        const std::optional<double> limit =
            read_limit_bytes(mount + (path == "/" ? std::string() : path) + "/" + limit_file);
        // cgroup v1 reports "no limit" as a number near 2^63.
        if (limit && *limit < 1e18 && (!tightest || *limit < *tightest)) tightest = limit;
        if (path == "/" || path.empty()) break;
        const std::size_t parent = path.rfind('/');
        path = parent == 0 || parent == std::string::npos ? "/" : path.substr(0, parent);
    }
}

// The memory limit of this process's control group: cgroup v2's memory.max, or the v1 memory
// controller's memory.limit_in_bytes.
std::optional<double> control_group_limit() {
    std::optional<double> tightest;
    std::ifstream groups("/proc/self/cgroup");
    for (std::string line; std::getline(groups, line);) {
        // "0::/path" (v2) or "4:memory:/path" (v1; the controllers a comma-separated list).
        const std::size_t first = line.find(':'), second = line.find(':', first + 1);
        if (first == std::string::npos || second == std::string::npos) continue;
        const std::string_view controllers = std::string_view(line).substr(first + 1, second - first - 1);
        const std::string path = line.substr(second + 1);
        if (line.starts_with("0::")) take_tightest_on_path("/sys/fs/cgroup", path, "memory.max", tightest);
        bool memory_controller = false;
        for (std::size_t at = 0; at <= controllers.size();) {
            const std::size_t comma = std::min(controllers.find(',', at), controllers.size());
            memory_controller = memory_controller || controllers.substr(at, comma - at) == "memory";
            at = comma + 1;
        }
        if (memory_controller) take_tightest_on_path("/sys/fs/cgroup/memory", path, "memory.limit_in_bytes", tightest);
    }
    return tightest;
}

std::optional<double> resource_limit(int resource) {
    rlimit limit{};
    if (::getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return std::nullopt;
    return static_cast<double>(limit.rlim_cur);
}

}  // namespace

HostMemory host_memory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    HostMemory memory{pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 16e9,
                      "this computer's physical memory"};
    const auto tighter = [&](std::optional<double> limit, const char* what) {
        if (limit && *limit < memory.bytes) memory = {*limit, what};
    };
    tighter(control_group_limit(), "the memory limit of its control group (a batch job's or a container's memory.max)");
    tighter(resource_limit(RLIMIT_AS), "its address-space limit (ulimit -v)");
    tighter(resource_limit(RLIMIT_DATA), "its data-size limit (ulimit -d)");
    return memory;
}

double host_memory_bytes() { return host_memory().bytes; }

void check_fits_host_memory(const std::string& file, const std::string& field, double bytes, const std::string& what) {
    const HostMemory host = host_memory();
    if (bytes > 0.5 * host.bytes)
        throw InputError(
            file, field,
            fmt::format("{} needs {:.1f} GB of this computer's memory; this process may use {:.1f} GB, set by {}, and "
                        "keeps half of it for the rest of the run",
                        what, bytes / 1e9, host.bytes / 1e9, host.limited_by));
}

namespace {
// The innermost activity an exception unwound on this thread, until the next one starts.
thread_local std::string unwound_activity;
}  // namespace

ScopedActivity::ScopedActivity(std::string what)
    : what_(std::move(what)), exceptions_at_start_(std::uncaught_exceptions()) {
    unwound_activity.clear();
}

ScopedActivity::~ScopedActivity() {
    // The innermost scope unwinds first: keep its name, not an enclosing one's.
    if (std::uncaught_exceptions() > exceptions_at_start_ && unwound_activity.empty()) unwound_activity = what_;
}

void keep_freed_memory_for_reuse() {
#if defined(__GLIBC__)
    // 32 MiB is the largest threshold glibc accepts on 64-bit hosts. Setting either turns off glibc's
    // own adjustment, which raises the threshold only after a block was handed back, and trims freely.
    constexpr int kLargestHeapBlock = 32 << 20;
    constexpr int kFreeKept = 1 << 30;
    mallopt(M_MMAP_THRESHOLD, kLargestHeapBlock);
    mallopt(M_TRIM_THRESHOLD, kFreeKept);
#endif
}

std::string out_of_memory_message() {
    const HostMemory host = host_memory();
    return fmt::format(
        "ran out of memory{}: this process may use {:.1f} GB, set by {}; a smaller volume, image or machine "
        "(fewer renderers, less backing store) needs less",
        unwound_activity.empty() ? std::string() : " " + unwound_activity, host.bytes / 1e9, host.limited_by);
}

}  // namespace pp5
