// One way to split a loop over threads: parallel_for runs work(begin, end, thread) over [0, n)
// cut into contiguous ranges, one per thread (thread 0 is the calling thread), and returns when
// all are done. The ranges are [n t / T, n (t + 1) / T) for t = 0..T−1, so work that writes only
// its own range's results gives the serial loop's result exactly. An exception thrown by any
// range is rethrown in the caller once every thread has joined (the first by thread index).
#pragma once

#include <cstddef>
#include <functional>

namespace stickslip {

// Upper bound on the threads of one loop (a guard against an absurd request, not a tuning).
inline constexpr int kMaxThreads = 64;

// Threads for a loop: `requested` if > 0, else std::thread::hardware_concurrency() (1 when it is
// unknown), clamped to [1, kMaxThreads].
int thread_count(int requested = 0);

using RangeWork = std::function<void(std::ptrdiff_t begin, std::ptrdiff_t end, int thread)>;

// T = min(threads, ceil(n / grain)) threads (≥ 1): a thread gets at least `grain` items, since
// starting one costs about as much as a few thousand cheap iterations. threads ≤ 1 or n ≤ grain:
// work(0, n, 0) in the caller. n ≥ 0, grain ≥ 1.
void parallel_for(std::ptrdiff_t n, int threads, const RangeWork& work, std::ptrdiff_t grain = 1);

}  // namespace stickslip
