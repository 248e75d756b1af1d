// Scoped limit on the number of BLAS threads (OpenBLAS only; a no-op with any other BLAS).
//
// CHOLMOD's supernodal factorisation is BLAS-3 and gains from threads; its single-vector solves
// are BLAS-2, memory bound, and on a busy 2-core machine OpenBLAS's threads make them several
// times slower (measured: 0.6 s instead of 0.15 s per Lanczos step at 100k DOFs, load 8). Lanczos
// therefore runs its solves under ScopedBlasThreads(1). The previous count is restored on exit.
// The OpenBLAS entry points are looked up at run time, so linking needs no OpenBLAS.
#pragma once

namespace stickslip {

class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int threads);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;
  // Whether the BLAS in use lets stickslip set its thread count (OpenBLAS).
  static bool supported();

 private:
  int previous_ = 0;  // 0: nothing to restore
};

}  // namespace stickslip
