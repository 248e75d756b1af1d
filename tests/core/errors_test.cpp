#include "core/errors.h"

#include <gtest/gtest.h>

namespace stickslip {
namespace {

TEST(InvalidInput, MessageNamesFileLineAndKey) {
  InvalidInput e({"case.yaml", 12, "contacts.kt"}, "must be positive, got -3");
  EXPECT_EQ(std::string(e.what()), "case.yaml:12: contacts.kt: must be positive, got -3");
  EXPECT_EQ(e.where().line, 12);
  EXPECT_EQ(e.message(), "must be positive, got -3");
}

TEST(Require, NamesFieldValueAndRule) {
  try {
    require(false, "HarmonicBalanceOptions::harmonics", "0", "harmonics >= 1");
    FAIL() << "require(false) did not throw";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()),
              "HarmonicBalanceOptions::harmonics = 0. Violated constraint: harmonics >= 1");
  }
  EXPECT_NO_THROW(require(true, "x", "1", "x > 0"));
}

TEST(Verify, ThrowsLogicErrorWithCondition) {
  EXPECT_THROW(STICKSLIP_VERIFY(1 + 1 == 3, "arithmetic"), std::logic_error);
  EXPECT_NO_THROW(STICKSLIP_VERIFY(1 + 1 == 2, "arithmetic"));
}

}  // namespace
}  // namespace stickslip
