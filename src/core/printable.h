// Text from users' files in messages: what reaches a terminal or a log must be readable and must
// not drive the terminal (an escape sequence, a carriage return that overwrites the line).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace stickslip {

// Position of the first byte of `s` that does not start (or continue) a well-formed UTF-8
// sequence (RFC 3629: no overlong forms, no surrogates U+D800..U+DFFF, nothing above U+10FFFF),
// or std::string_view::npos when the whole of `s` is valid UTF-8.
std::size_t first_invalid_utf8(std::string_view s);

// `s` with every byte that is not printable written as \xNN (two upper-case hex digits):
// the ASCII control characters (0x00..0x1F, including tab and newline, and 0x7F) and every byte
// that is not part of a well-formed UTF-8 sequence. Printable ASCII and well-formed UTF-8
// sequences are kept, so the result of printable() is its own printable() (idempotent).
std::string printable(std::string_view s);

}  // namespace stickslip
