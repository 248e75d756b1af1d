// Numbers in messages. std::to_string(double) prints "%f": 1e-9 becomes "0.000000" and 2.5e8
// "250000000.000000", so an error message would misquote the value it complains about. Every
// message outside src/cli formats a double with one of these instead.
#pragma once

#include <string>

namespace stickslip {

// The shortest text that reads back as exactly v (std::to_chars): a value from the user's file
// is echoed as the same number (0.3, 1e-09, 1234.5, 2.5e+08: the shorter of the fixed and the
// exponent form); nan, inf and -inf as such.
std::string format_number(double v);

// At most `significant_digits` (1..17) significant digits, printf's %g: for computed values
// (a residual, a determinant, a distance) whose last digits say nothing.
std::string format_number(double v, int significant_digits);

}  // namespace stickslip
