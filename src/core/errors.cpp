#include "core/errors.h"

#include <utility>

#include "core/printable.h"

namespace stickslip {

std::string format_location(const SourceLocation& where) {
  std::string s;
  if (!where.file.empty()) {
    s += where.file;
    if (where.line > 0) {
      s += ':';
      s += std::to_string(where.line);
    }
    s += ": ";
  }
  if (!where.key.empty()) {
    s += where.key;
    s += ": ";
  }
  return s;
}

// The file name, the key and the message may carry bytes from users' files: what() and message()
// hold them escaped (core/printable.h); where() keeps the file and key as given.
InvalidInput::InvalidInput(const std::string& message)
    : std::runtime_error(printable(message)), message_(printable(message)) {}

InvalidInput::InvalidInput(SourceLocation where, const std::string& message)
    : std::runtime_error(printable(format_location(where) + message)),
      where_(std::move(where)),
      message_(printable(message)) {}

void require(bool ok, const std::string& field, const std::string& value,
             const std::string& rule) {
  if (!ok) {
    throw InvalidInput(field + " = " + value + ". Violated constraint: " + rule);
  }
}

void verify_failed(const char* condition, const char* file, int line, const std::string& message) {
  throw std::logic_error(std::string(file) + ":" + std::to_string(line) +
                         ": internal error: " + condition + " failed: " + message);
}

}  // namespace stickslip
