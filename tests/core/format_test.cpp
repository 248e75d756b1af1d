// format_number (core/format.h): values echoed exactly as written, small and large values not
// flattened to "0.000000" as std::to_string does, and the %g form of computed values.
#include "core/format.h"

#include <cstdlib>
#include <limits>
#include <string>

#include <gtest/gtest.h>

namespace stickslip {
namespace {

TEST(FormatNumber, ShortestTextThatReadsBackExactly) {
  EXPECT_EQ(format_number(1e-9), "1e-09");
  EXPECT_EQ(format_number(0.3), "0.3");
  EXPECT_EQ(format_number(250000000.0), "2.5e+08");  // the shorter of %f and %e forms
  EXPECT_EQ(format_number(1234.5), "1234.5");
  EXPECT_EQ(format_number(-4.5e20), "-4.5e+20");
  EXPECT_EQ(format_number(0.0), "0");
  EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
  // Round trip over awkward values: the text parses back to the same double.
  for (double v : {0.1 + 0.2, 1.0 / 3.0, 6.02214076e23, 4.9e-324, 1.7976931348623157e308,
                   -2.2250738585072014e-308}) {
    const std::string s = format_number(v);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
}

TEST(FormatNumber, SignificantDigitsForComputedValues) {
  EXPECT_EQ(format_number(1.0 / 3.0, 6), "0.333333");
  EXPECT_EQ(format_number(1.23456789e-12, 3), "1.23e-12");
  EXPECT_EQ(format_number(123456789.0, 4), "1.235e+08");
  EXPECT_EQ(format_number(2.0, 6), "2");
  EXPECT_EQ(format_number(0.5, 0), "0.5");  // clamped to one digit
}

}  // namespace
}  // namespace stickslip
