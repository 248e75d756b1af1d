#include "linalg/blas_threads.h"

#include <dlfcn.h>

namespace stickslip {

namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

GetThreads get_threads() {
  static const auto f =
      reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return f;
}
SetThreads set_threads() {
  static const auto f =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  return f;
}

}  // namespace

bool ScopedBlasThreads::supported() { return get_threads() != nullptr && set_threads() != nullptr; }

ScopedBlasThreads::ScopedBlasThreads(int threads) {
  if (!supported() || threads < 1) return;
  previous_ = get_threads()();
  if (previous_ != threads) {
    set_threads()(threads);
  } else {
    previous_ = 0;
  }
}

ScopedBlasThreads::~ScopedBlasThreads() {
  if (previous_ > 0) set_threads()(previous_);
}

}  // namespace stickslip
