// libFuzzer harness for one file reader of src/io (fuzz_targets.h): built once per reader with
// STICKSLIP_FUZZ_TARGET set to the reader's name (fuzz/CMakeLists.txt). An input passes when the
// reader returns or throws InvalidInput naming its source; any other exception aborts, so
// libFuzzer records the input as a crash (sanitizers, hangs and huge allocations are caught by
// libFuzzer itself: -timeout, -malloc_limit_mb, -rss_limit_mb).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string_view>
#include <typeinfo>

#include "core/errors.h"
#include "fuzz_targets.h"

namespace {

const stickslip::fuzz::Target& this_target() {
  for (const auto& t : stickslip::fuzz::targets()) {
    if (std::strcmp(t.name, STICKSLIP_FUZZ_TARGET) == 0) return t;
  }
  std::fprintf(stderr, "no fuzz target named %s\n", STICKSLIP_FUZZ_TARGET);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const stickslip::fuzz::Target& target = this_target();
  static const stickslip::fuzz::Context context{STICKSLIP_FUZZ_CASE_DIR};
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    target.feed(bytes, context);
  } catch (const stickslip::InvalidInput& e) {
    if (e.where().file.empty() || e.message().empty()) {
      std::fprintf(stderr, "InvalidInput without a file name or a message: %s\n", e.what());
      std::abort();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uncaught %s: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}
