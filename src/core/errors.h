// stickslip's three error channels (docs/architecture.md):
//  1. Bad input (a file, a case-file key, an option out of range) throws InvalidInput at the
//     boundary, naming where it came from (file, line, key) and the rule it broke.
//  2. A numerical outcome (a Newton solve that did not converge, a factorisation that failed) is a
//     value returned to the caller (a Summary struct with a termination type and a message).
//  3. Internal invariants use STICKSLIP_ASSERT (debug builds only); STICKSLIP_VERIFY is always on
//     and throws std::logic_error: for invariants that are cheap and whose violation would
//     otherwise give a silent wrong answer.
#pragma once

#include <stdexcept>
#include <string>

namespace stickslip {

// Where a piece of input came from. Empty file = not from a file (e.g. an options struct).
struct SourceLocation {
  std::string file;
  int line = 0;      // 1-based; 0 = unknown
  std::string key;   // case-file key or field name; may be empty
};

// "file:line: key: message" with the parts that are known (as given, not escaped).
std::string format_location(const SourceLocation& where);

// what() and message() show bytes that are not printable (control characters, bytes that are not
// UTF-8) as \xNN (core/printable.h), so a name read from a damaged file cannot drive the terminal.
class InvalidInput : public std::runtime_error {
 public:
  explicit InvalidInput(const std::string& message);
  InvalidInput(SourceLocation where, const std::string& message);
  const SourceLocation& where() const { return where_; }
  // The message without the location prefix.
  const std::string& message() const { return message_; }

 private:
  SourceLocation where_;
  std::string message_;
};

// Throws InvalidInput("<field> = <value>. Violated constraint: <rule>") unless ok.
// For validate() functions of options structs (Ceres style).
void require(bool ok, const std::string& field, const std::string& value, const std::string& rule);

[[noreturn]] void verify_failed(const char* condition, const char* file, int line,
                                const std::string& message);

}  // namespace stickslip

#define STICKSLIP_VERIFY(cond, msg)                                          \
  do {                                                                       \
    if (!(cond)) ::stickslip::verify_failed(#cond, __FILE__, __LINE__, msg); \
  } while (0)

#ifdef NDEBUG
#define STICKSLIP_ASSERT(cond) ((void)0)
#else
#define STICKSLIP_ASSERT(cond) STICKSLIP_VERIFY(cond, "internal assertion")
#endif
