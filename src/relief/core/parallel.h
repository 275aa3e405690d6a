#pragma once
// Parallel loops over TBB; thread count set once per process by ThreadLimit.
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <memory>

namespace relief {

// Caps TBB's worker count while alive; threads <= 0 means "all cores".
class ThreadLimit {
public:
    explicit ThreadLimit(int threads);
    static int current();

private:
    std::unique_ptr<tbb::global_control> m_control;
};

// Calls body(begin, end) on disjoint sub-ranges of [0, count), in parallel.
template <class Body>
void parallelRanges(int64_t count, int64_t grain, Body&& body) {
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, count, grain > 0 ? grain : 1),
                      [&](const tbb::blocked_range<int64_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace relief
