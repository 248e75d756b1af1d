// The test utility tests/derivative_check.h itself: a right Jacobian gives slope 2, a wrong one
// slope 1 (so the check can fail), a linear map round-off at every step.
#include "../derivative_check.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Core>

namespace stickslip {
namespace {

Eigen::VectorXd r(const Eigen::Vector2d& x) {
  return Eigen::Vector2d(std::sin(x[0]) * x[1], std::exp(x[1]) + x[0] * x[0]);
}

Eigen::Matrix2d jacobian(const Eigen::Vector2d& x) {
  Eigen::Matrix2d J;
  J << std::cos(x[0]) * x[1], std::sin(x[0]), 2 * x[0], std::exp(x[1]);
  return J;
}

TEST(DerivativeCheck, SlopeIsTwoForTheRightJacobianAndOneForAWrongOne) {
  const Eigen::Vector2d x(0.7, -0.3), d(0.4, 0.9);
  auto at = [&](double h) { return r(x + h * d); };
  const testing::TaylorRemainder right = testing::taylor_remainder(at, r(x), jacobian(x) * d);
  EXPECT_FALSE(right.linear);
  EXPECT_NEAR(right.slope, 2.0, 0.05) << right.describe();
  testing::expect_taylor_slope(right);
  Eigen::Matrix2d wrong = jacobian(x);
  wrong(0, 1) *= 1.001;  // a 0.1 % error in one entry
  const testing::TaylorRemainder bad = testing::taylor_remainder(at, r(x), wrong * d);
  EXPECT_NEAR(bad.slope, 1.0, 0.05) << bad.describe();
  EXPECT_LT(bad.slope, testing::kTaylorSlopeMin);
}

TEST(DerivativeCheck, LinearMapIsRoundOffAtEveryStep) {
  Eigen::Matrix2d A;
  A << 3, -1, 2, 5;
  const Eigen::Vector2d x(1e-3, 2e-3), d(1, -1);
  const testing::TaylorRemainder t =
      testing::taylor_remainder([&](double h) { return Eigen::VectorXd(A * (x + h * d)); },
                                A * x, A * d);
  EXPECT_TRUE(t.linear) << t.describe();
}

}  // namespace
}  // namespace stickslip
