// What a run may allocate: the least of physical memory and the process's own limits, and, when an
// allocation fails all the same, a message that says what was being built.

#include "sim/core/host_memory.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <new>

namespace pp5 {
namespace {

TEST(HostMemory, IsNoMoreThanThePhysicalMemoryOrTheProcessLimits) {
    const HostMemory memory = host_memory();
    const double physical =
        static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
    EXPECT_GT(memory.bytes, 0);
    EXPECT_LE(memory.bytes, physical);
    for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit limit{};
        ASSERT_EQ(::getrlimit(resource, &limit), 0);
        if (limit.rlim_cur != RLIM_INFINITY) {
            EXPECT_LE(memory.bytes, static_cast<double>(limit.rlim_cur));
        }
    }
    EXPECT_FALSE(memory.limited_by.empty());
}

TEST(HostMemory, AFailedAllocationNamesTheInnermostActivityItUnwound) {
    try {
        const ScopedActivity outer("loading the volume");
        const ScopedActivity inner("building the pyramid");
        throw std::bad_alloc();
    } catch (const std::bad_alloc&) {
        const std::string message = out_of_memory_message();
        EXPECT_NE(message.find("ran out of memory building the pyramid:"), std::string::npos) << message;
        EXPECT_EQ(message.find("loading the volume"), std::string::npos) << message;
    }
    // A new activity that finishes clears the name left behind.
    { const ScopedActivity later("writing the pictures"); }
    EXPECT_NE(out_of_memory_message().find("ran out of memory: "), std::string::npos) << out_of_memory_message();
}

}  // namespace
}  // namespace pp5
