#pragma once
// The project's parallel loops: oneTBB's parallel_for and parallel_sort, called through here so that a
// ThreadSanitizer build checks the project's own code rather than TBB's.
//
// Debian's libtbb is not built with ThreadSanitizer: its scheduler's synchronisation (the task deques,
// the fork and join) is invisible to TSan, while the task objects its headers build are instrumented in
// our binaries, so a plain TSan build reports TBB's own hand-offs by the thousand. Under TSan these
// loops therefore run on a back end TSan can see whole: the range is split with its own splitting
// constructor (as TBB would split it) and the pieces are taken by std::threads, as many as TBB's
// max_allowed_parallelism allows, so bodies really run concurrently and a race between two bodies is
// still reported. Outside TSan the loops are TBB's own calls, unchanged.

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#if defined(__SANITIZE_THREAD__)
#define PP5_UNDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PP5_UNDER_TSAN 1
#endif
#endif

#ifdef PP5_UNDER_TSAN
#include <atomic>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#endif

namespace pp5 {

#ifdef PP5_UNDER_TSAN
namespace parallel_detail {
// Runs body over range on std::threads: the range split into a few pieces per thread, each piece
// taken by the next free thread. The first exception a body throws is rethrown after every thread
// has joined, as TBB would.
template <class Range, class Body>
void run_on_threads(const Range& range, const Body& body) {
    const std::size_t threads =
        std::max<std::size_t>(1, tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    const std::size_t wanted = 4 * threads;
    std::vector<Range> pieces;
    std::deque<Range> pending{range};
    while (!pending.empty()) {
        Range piece = pending.front();
        pending.pop_front();
        if (!piece.empty() && piece.is_divisible() && pieces.size() + pending.size() + 2 <= wanted) {
            Range other(piece, tbb::split());
            pending.push_back(piece);
            pending.push_back(other);
        } else if (!piece.empty()) {
            pieces.push_back(piece);
        }
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&] {
        for (std::size_t i = next++; i < pieces.size(); i = next++) {
            try {
                body(pieces[i]);
            } catch (...) {
                const std::lock_guard<std::mutex> lock(failure_mutex);
                if (!failure) failure = std::current_exception();
            }
        }
    };
    std::vector<std::thread> helpers;
    for (std::size_t t = 1; t < std::min(threads, pieces.size()); ++t) helpers.emplace_back(work);
    work();
    for (std::thread& helper : helpers) helper.join();
    if (failure) std::rethrow_exception(failure);
}
}  // namespace parallel_detail
#endif

// tbb::parallel_for(range, body): body(const Range&) over sub-ranges.
template <class Range, class Body>
void parallel_for(const Range& range, const Body& body) {
#ifdef PP5_UNDER_TSAN
    parallel_detail::run_on_threads(range, body);
#else
    tbb::parallel_for(range, body);
#endif
}

// tbb::parallel_for(first, last, body): body(index) for every index in [first, last).
template <class Index, class Body>
void parallel_for(Index first, Index last, const Body& body) {
#ifdef PP5_UNDER_TSAN
    parallel_detail::run_on_threads(tbb::blocked_range<Index>(first, last),
                                    [&body](const tbb::blocked_range<Index>& r) {
                                        for (Index i = r.begin(); i != r.end(); ++i) body(i);
                                    });
#else
    tbb::parallel_for(first, last, body);
#endif
}

// tbb::parallel_sort. A TSan build sorts on one thread: the callers' comparators are total orders,
// so the result is the same.
template <class Iterator, class Compare>
void parallel_sort(Iterator first, Iterator last, const Compare& less) {
#ifdef PP5_UNDER_TSAN
    std::sort(first, last, less);
#else
    tbb::parallel_sort(first, last, less);
#endif
}

}  // namespace pp5
