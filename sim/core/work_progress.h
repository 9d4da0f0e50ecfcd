#pragma once
// Progress of long work inside one call (scan-converting 100,000 polygons, say), for a frontend that
// wants to show it. The work reports to whatever listener the calling thread has installed, usually
// none; a frontend installs one for the length of a call with ScopedWorkListener. Per thread, so a
// sweep's parallel points neither share a listener nor need locks, and a listener never changes a
// result.

#include <cstddef>
#include <string_view>

namespace pp5 {

class WorkListener {
public:
    virtual ~WorkListener() = default;
    // `done` of `total` steps of `stage` ("scan-converting polygons") are finished.
    virtual void on_work(std::string_view stage, std::size_t done, std::size_t total) = 0;
};

// Tells this thread's listener, if any.
void report_work(std::string_view stage, std::size_t done, std::size_t total);

// Installs a listener for this thread until it goes out of scope (restoring the one before).
class ScopedWorkListener {
public:
    explicit ScopedWorkListener(WorkListener& listener);
    ~ScopedWorkListener();
    ScopedWorkListener(const ScopedWorkListener&) = delete;
    ScopedWorkListener& operator=(const ScopedWorkListener&) = delete;

private:
    WorkListener* previous_;
};

}  // namespace pp5
