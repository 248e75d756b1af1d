#include "core/format.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>

namespace stickslip {

std::string format_number(double v) {
  std::array<char, 64> buffer{};  // the longest shortest form of a double is 24 characters
  const std::to_chars_result r = std::to_chars(buffer.data(), buffer.data() + buffer.size(), v);
  return std::string(buffer.data(), r.ptr);
}

std::string format_number(double v, int significant_digits) {
  const int digits = std::clamp(significant_digits, 1, 17);
  std::array<char, 64> buffer{};
  const int n = std::snprintf(buffer.data(), buffer.size(), "%.*g", digits, v);
  return std::string(buffer.data(), static_cast<size_t>(std::clamp(n, 0, 63)));
}

}  // namespace stickslip
