// parallel_for (core/parallel.h): the ranges cover [0, n) once, the result equals the serial
// loop's bit for bit, an exception in any range reaches the caller, and thread_count's rule.
#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace stickslip {
namespace {

TEST(ParallelFor, ResultIsTheSerialLoopsExactly) {
  const std::ptrdiff_t n = 10007;
  auto value = [](std::ptrdiff_t i) { return std::sin(0.001 * static_cast<double>(i)) * 1e3; };
  std::vector<double> serial(static_cast<size_t>(n));
  for (std::ptrdiff_t i = 0; i < n; ++i) serial[static_cast<size_t>(i)] = value(i);
  for (int threads : {1, 2, 3, 7, 64}) {
    std::vector<double> out(static_cast<size_t>(n), -1.0);
    std::vector<std::atomic<int>> visits(static_cast<size_t>(n));
    parallel_for(n, threads, [&](std::ptrdiff_t b, std::ptrdiff_t e, int) {
      for (std::ptrdiff_t i = b; i < e; ++i) {
        out[static_cast<size_t>(i)] = value(i);
        ++visits[static_cast<size_t>(i)];
      }
    });
    EXPECT_EQ(out, serial) << threads;
    for (const auto& v : visits) ASSERT_EQ(v.load(), 1);
  }
}

TEST(ParallelFor, ThreadIndicesAreDistinctAndGrainLimitsTheThreads) {
  std::vector<int> seen;
  std::mutex m;
  parallel_for(
      100, 8,
      [&](std::ptrdiff_t b, std::ptrdiff_t e, int t) {
        EXPECT_GE(e - b, 25);
        const std::lock_guard<std::mutex> lock(m);
        seen.push_back(t);
      },
      25);
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2, 3}));  // ceil(100 / 25) = 4 threads
  int calls = 0;
  parallel_for(0, 8, [&](std::ptrdiff_t b, std::ptrdiff_t e, int) {
    ++calls;
    EXPECT_EQ(b, e);
  });
  EXPECT_EQ(calls, 1);
}

TEST(ParallelFor, ExceptionsReachTheCallerAfterEveryThreadJoined) {
  std::atomic<int> finished{0};
  EXPECT_THROW(parallel_for(4000, 4,
                            [&](std::ptrdiff_t, std::ptrdiff_t, int t) {
                              if (t == 2) throw std::runtime_error("range 2 failed");
                              std::this_thread::sleep_for(std::chrono::milliseconds(20));
                              ++finished;
                            }),
               std::runtime_error);
  EXPECT_EQ(finished.load(), 3);  // the other ranges ran to their end before the rethrow
  EXPECT_THROW(parallel_for(10, 1,
                            [](std::ptrdiff_t, std::ptrdiff_t, int) {
                              throw std::invalid_argument("serial");
                            }),
               std::invalid_argument);
}

TEST(ParallelFor, ThreadCountUsesTheHardwareUnlessAsked) {
  const unsigned hardware = std::thread::hardware_concurrency();
  EXPECT_EQ(thread_count(0), hardware == 0 ? 1 : std::min<int>(hardware, kMaxThreads));
  EXPECT_EQ(thread_count(3), 3);
  EXPECT_EQ(thread_count(1000), kMaxThreads);
}

}  // namespace
}  // namespace stickslip
