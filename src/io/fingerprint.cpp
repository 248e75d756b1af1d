#include "io/fingerprint.h"

#include <cstdint>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"

namespace stickslip {
namespace {

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;  // FNV-1a 64 offset basis
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;        // FNV 64 prime

std::uint64_t fnv1a(std::uint64_t h, const char* data, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= kFnvPrime;
  }
  return h;
}

}  // namespace

std::string fingerprint_hex(const std::string& text) {
  return fmt::format("{:016x}", fnv1a(kFnvOffset, text.data(), text.size()));
}

std::string file_fingerprint_hex(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot read the file");
  std::uint64_t h = kFnvOffset;
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    h = fnv1a(h, buffer.data(), static_cast<size_t>(in.gcount()));
  }
  return fmt::format("{:016x}", h);
}

}  // namespace stickslip
