#pragma once
// The project's parallel loops: oneTBB's parallel_for and parallel_sort, called through here so that a
// ThreadSanitizer build can see what they guarantee.
//
// Debian's libtbb is not built with ThreadSanitizer, so the fork and join inside it (its scheduler's
// atomics) are invisible to TSan, and every access a loop body makes to data the caller prepared
// would be reported as a race. Under TSan these wrappers state exactly TBB's contract and nothing
// more: everything the caller did before the loop happens before every body, and every body happens
// before the loop returns. Bodies are not ordered among themselves, so two bodies that touch the same
// data without synchronising are still reported: that is the race a verdict should mean.
// Outside TSan the wrappers are TBB's own calls, unchanged.

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#if defined(__SANITIZE_THREAD__)
#define PP5_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PP5_TSAN 1
#endif
#endif

#ifdef PP5_TSAN
#include <sanitizer/tsan_interface.h>
#endif

namespace pp5 {

#ifdef PP5_TSAN
namespace parallel_detail {
// The happens-before edges of one fork and join, as TSan annotations on two addresses of its own.
class ForkJoin {
public:
    ForkJoin() { __tsan_release(&fork_); }
    void body_starts() { __tsan_acquire(&fork_); }
    void body_ends() { __tsan_release(&join_); }
    ~ForkJoin() { __tsan_acquire(&join_); }
    ForkJoin(const ForkJoin&) = delete;
    ForkJoin& operator=(const ForkJoin&) = delete;

private:
    char fork_ = 0;
    char join_ = 0;
};

template <class Body>
auto annotated(ForkJoin& edges, const Body& body) {
    return [&edges, &body](auto&&... args) {
        edges.body_starts();
        body(args...);
        edges.body_ends();
    };
}
}  // namespace parallel_detail
#endif

// tbb::parallel_for(range, body): body(const Range&) over sub-ranges.
template <class Range, class Body>
void parallel_for(const Range& range, const Body& body) {
#ifdef PP5_TSAN
    parallel_detail::ForkJoin edges;
    tbb::parallel_for(range, parallel_detail::annotated(edges, body));
#else
    tbb::parallel_for(range, body);
#endif
}

// tbb::parallel_for(first, last, body): body(index) for every index in [first, last).
template <class Index, class Body>
void parallel_for(Index first, Index last, const Body& body) {
#ifdef PP5_TSAN
    parallel_detail::ForkJoin edges;
    tbb::parallel_for(first, last, parallel_detail::annotated(edges, body));
#else
    tbb::parallel_for(first, last, body);
#endif
}

// tbb::parallel_sort. Its element moves happen inside TBB's tasks, where no annotation of the
// comparator can reach, so a TSan build sorts on one thread: the callers' comparators are total
// orders, so the result is the same.
template <class Iterator, class Compare>
void parallel_sort(Iterator first, Iterator last, const Compare& less) {
#ifdef PP5_TSAN
    std::sort(first, last, less);
#else
    tbb::parallel_sort(first, last, less);
#endif
}

}  // namespace pp5
