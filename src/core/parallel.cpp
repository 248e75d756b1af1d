#include "core/parallel.h"

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

#include "core/errors.h"

namespace stickslip {

int thread_count(int requested) {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return std::clamp(requested > 0 ? requested : hardware, 1, kMaxThreads);
}

void parallel_for(std::ptrdiff_t n, int threads, const RangeWork& work, std::ptrdiff_t grain) {
  STICKSLIP_VERIFY(n >= 0 && grain >= 1, "parallel_for: n >= 0 and grain >= 1");
  const std::ptrdiff_t most = (n + grain - 1) / grain;
  const int count = static_cast<int>(
      std::clamp<std::ptrdiff_t>(std::min<std::ptrdiff_t>(threads, most), 1, kMaxThreads));
  if (count == 1) {
    work(0, n, 0);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<size_t>(count));
  auto run = [&](int t) {
    try {
      work(n * t / count, n * (t + 1) / count, t);
    } catch (...) {
      errors[static_cast<size_t>(t)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(count - 1));
  for (int t = 1; t < count; ++t) pool.emplace_back(run, t);
  run(0);
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace stickslip
