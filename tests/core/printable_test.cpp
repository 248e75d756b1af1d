#include "core/printable.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace stickslip {
namespace {

TEST(Printable, KeepsAsciiAndWellFormedUtf8) {
  EXPECT_EQ(printable("beam 1: \"x\" \\ ok"), "beam 1: \"x\" \\ ok");
  EXPECT_EQ(printable("Stra\xC3\x9F"
                      "e \xE2\x82\xAC \xF0\x9F\x98\x80"),
            "Stra\xC3\x9F"
            "e \xE2\x82\xAC \xF0\x9F\x98\x80");
}

TEST(Printable, EscapesControlCharactersAndBytesThatAreNotUtf8) {
  EXPECT_EQ(printable(std::string("a\x1b[2Jb\r\n\t\x7f", 10)), "a\\x1B[2Jb\\x0D\\x0A\\x09\\x7F");
  EXPECT_EQ(printable(std::string("x\0y", 3)), "x\\x00y");
  // A lone continuation byte, a truncated sequence, an overlong '/', a surrogate, > U+10FFFF.
  EXPECT_EQ(printable("\x80"), "\\x80");
  EXPECT_EQ(printable("\xE2\x82"), "\\xE2\\x82");
  EXPECT_EQ(printable("\xC0\xAF"), "\\xC0\\xAF");
  EXPECT_EQ(printable("\xED\xA0\x80"), "\\xED\\xA0\\x80");
  EXPECT_EQ(printable("\xF4\x90\x80\x80"), "\\xF4\\x90\\x80\\x80");
  const std::string once = printable("\xff\x01");
  EXPECT_EQ(printable(once), once);
}

TEST(FirstInvalidUtf8, PositionOfTheFirstBadByte) {
  EXPECT_EQ(first_invalid_utf8("plain"), std::string_view::npos);
  EXPECT_EQ(first_invalid_utf8("\xC3\xA9t\xC3\xA9"), std::string_view::npos);
  EXPECT_EQ(first_invalid_utf8("ab\xFF"), 2u);
  EXPECT_EQ(first_invalid_utf8("\xC3\xA9\xC3"), 2u);  // truncated at the end
  EXPECT_EQ(first_invalid_utf8("\xE0\x80\x80"), 0u);  // overlong
}

TEST(InvalidInput, EscapesWhatIsNotPrintable) {
  const InvalidInput e({"a\nb.yaml", 3, "bodies.x\x1b"}, "node set \xff");
  EXPECT_EQ(std::string(e.what()), "a\\x0Ab.yaml:3: bodies.x\\x1B: node set \\xFF");
  EXPECT_EQ(e.message(), "node set \\xFF");
}

}  // namespace
}  // namespace stickslip
