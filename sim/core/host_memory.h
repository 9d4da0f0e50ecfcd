#pragma once
// The memory this process may use, and the one test every allocation an input decides makes first:
// whether it fits in half of it. Beyond that a run is refused up front, saying how much it would need,
// instead of allocating until the system kills it (the other half is for what the run computes
// besides).
//
// What the process may use is the least of the computer's physical memory, the memory limit of its
// control group (a Slurm job's or a container's, cgroup v2 or v1) and its address-space and data-size
// limits (ulimit -v, ulimit -d): a run refused only at the physical size would be killed, or see
// std::bad_alloc, long before reaching it.

#include <string>

namespace pp5 {

struct HostMemory {
    double bytes = 0;
    std::string limited_by;  // "this computer's physical memory", "its control group's memory.max", ...
};

HostMemory host_memory();
double host_memory_bytes();

// Throws InputError(file, field, "<what> needs N GB ...") when `bytes` exceed half of host_memory().
void check_fits_host_memory(const std::string& file, const std::string& field, double bytes, const std::string& what);

// Asks the C library to keep the memory a frame frees for the next frame instead of handing it back
// to the system: every frame allocates its recorded work and scratch buffers afresh, tens of megabytes,
// and memory returned and taken again is zeroed page by page by the kernel (a third of a fixed-light
// frame's host time on ch2 at 512x512). Blocks up to 32 MiB then come from the heap, and the heap gives
// back only what it holds free beyond 1 GiB. For programs that render frame after frame (the CLI, the
// benchmarks); a library leaves its host process's allocator alone. Does nothing off glibc.
void keep_freed_memory_for_reuse();

// What the CLI says when an allocation fails all the same: what was being built (the innermost
// ScopedActivity the failure unwound on this thread), how much the process may use, and why.
std::string out_of_memory_message();

// Names what this thread is doing ("loading ch2.nii.gz") for out_of_memory_message. An exception that
// unwinds through it leaves its name behind, so the handler that catches the exception can still say
// what was being built after the scope is gone.
class ScopedActivity {
public:
    explicit ScopedActivity(std::string what);
    ~ScopedActivity();
    ScopedActivity(const ScopedActivity&) = delete;
    ScopedActivity& operator=(const ScopedActivity&) = delete;

private:
    std::string what_;
    int exceptions_at_start_;
};

}  // namespace pp5
