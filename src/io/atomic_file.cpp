#include "io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <locale>

#include "core/errors.h"

namespace stickslip {
namespace {

// A unique temporary name next to `path` (same directory, so rename() stays on one file system).
std::string temporary_name(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  const SourceLocation where{path, 0, ""};
  const std::string tmp = temporary_name(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw InvalidInput(
          where, std::string("cannot open a temporary file for writing: ") + std::strerror(errno));
    }
    out.imbue(std::locale::classic());
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw InvalidInput(where, "write failed (disk full or I/O error)");
    }
    out.close();
    if (out.fail()) {
      std::remove(tmp.c_str());
      throw InvalidInput(where, "closing the temporary file failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InvalidInput(where, "cannot rename the temporary file onto the target: " + ec.message());
  }
}

}  // namespace stickslip
