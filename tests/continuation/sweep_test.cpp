#include "continuation/sweep.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "test_systems.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using testing::FunctionSystem;

// x³ + x − λ: one real root for every λ, Cardano's formula.
FunctionSystem monotone_cubic() {
  return FunctionSystem(1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
    R(0) = x(0) * x(0) * x(0) + x(0) - l;
    if (J) (*J)(0, 0) = 3 * x(0) * x(0) + 1;
    if (Rl) (*Rl)(0) = -1;
  });
}
double cardano_root(double l) {
  const double d = std::sqrt(l * l / 4 + 1.0 / 27);
  return std::cbrt(l / 2 + d) + std::cbrt(l / 2 - d);
}

// atan(x − λ), root x = λ; plain Newton diverges when |x − λ| > 1.3917.
FunctionSystem shifted_atan() {
  return FunctionSystem(1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
    const double e = x(0) - l;
    R(0) = std::atan(e);
    if (J) (*J)(0, 0) = 1 / (1 + e * e);
    if (Rl) (*Rl)(0) = -1 / (1 + e * e);
  });
}

// x² − λ: roots ±√λ, none for λ < 0.
FunctionSystem parabola() {
  return FunctionSystem(1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
    R(0) = x(0) * x(0) - l;
    if (J) (*J)(0, 0) = 2 * x(0);
    if (Rl) (*Rl)(0) = -1;
  });
}

// |x − x_exact| for a converged scalar root: |R| <= 1e-8 and |dR/dx| >= 1 in these systems.
constexpr double kRootTolerance = 1e-8;

TEST(SteppedSweep, TestSystemJacobiansMatchFiniteDifferences) {
  testing::expect_jacobians_match_finite_differences(monotone_cubic(), VectorXd{{0.8}}, 1.5);
  testing::expect_jacobians_match_finite_differences(shifted_atan(), VectorXd{{0.3}}, -0.4);
  testing::expect_jacobians_match_finite_differences(parabola(), VectorXd{{1.2}}, 2.0);
}

TEST(SteppedSweep, FollowsASmoothBranchAtTheRequestedParameters) {
  const FunctionSystem sys = monotone_cubic();
  std::vector<double> lambdas;
  for (int i = 0; i <= 40; ++i) lambdas.push_back(-10 + 0.5 * i);
  int iterations[2] = {0, 0};
  for (bool secant : {false, true}) {
    SteppedSweepOptions options;
    options.secant_predictor = secant;
    const ContinuationResult r = stepped_sweep(sys, VectorXd{{-2.0}}, lambdas, options);
    ASSERT_TRUE(r.completed) << r.message;
    ASSERT_EQ(r.points.size(), lambdas.size());
    for (std::size_t i = 0; i < lambdas.size(); ++i) {
      EXPECT_EQ(r.points[i].lambda, lambdas[i]);
      EXPECT_TRUE(r.points[i].newton.converged());
      EXPECT_EQ(r.points[i].step_halvings, 0);
      EXPECT_NEAR(r.points[i].x(0), cardano_root(lambdas[i]), kRootTolerance);
      iterations[secant] += r.points[i].newton.iterations;
    }
  }
  // The secant guess is first-order accurate in the step, the previous point zeroth-order.
  EXPECT_LT(iterations[1], iterations[0]);
}

TEST(SteppedSweep, HalvesTheStepToRecoverAFailedPoint) {
  const FunctionSystem sys = shifted_atan();
  SteppedSweepOptions options;
  options.newton.min_step_fraction = 1.0;  // plain Newton: fails from |x − λ| = 3 or 1.5
  const std::vector<double> lambdas{0.0, 1.0, 4.0};
  ContinuationResult r = stepped_sweep(sys, VectorXd{{0.0}}, lambdas, options);
  ASSERT_TRUE(r.completed) << r.message;
  ASSERT_EQ(r.points.size(), 3u);
  EXPECT_EQ(r.points[1].step_halvings, 0);
  // Step 3 fails, 1.5 fails (|atan| grows), 0.75 converges: two halvings.
  EXPECT_EQ(r.points[2].step_halvings, 2);
  EXPECT_EQ(r.points[2].lambda, 4.0);
  EXPECT_NEAR(r.points[2].x(0), 4.0, kRootTolerance);

  // With a single halving allowed, λ = 4 is reached by the arc-length fallback; without that
  // fallback it cannot be reached: it is reported, not dropped.
  options.max_step_halvings = 1;
  r = stepped_sweep(sys, VectorXd{{0.0}}, lambdas, options);
  ASSERT_TRUE(r.completed) << r.message;
  EXPECT_TRUE(r.points[2].by_arclength);
  EXPECT_EQ(r.points[2].lambda, 4.0);
  EXPECT_NEAR(r.points[2].x(0), 4.0, kRootTolerance);
  options.jump_max_points = 0;
  r = stepped_sweep(sys, VectorXd{{0.0}}, lambdas, options);
  EXPECT_FALSE(r.completed);
  ASSERT_EQ(r.points.size(), 3u);
  EXPECT_FALSE(r.points[2].newton.converged());
  EXPECT_EQ(r.points[2].lambda, 4.0);
  EXPECT_NE(r.message.find("not converged at lambda = 4"), std::string::npos) << r.message;
  // The failed point says why: Newton's message and the halving that did not get there.
  EXPECT_NE(r.points[2].failure.find("Newton: "), std::string::npos) << r.points[2].failure;
  EXPECT_NE(r.points[2].failure.find("1 step halving did not reach it"), std::string::npos)
      << r.points[2].failure;
  EXPECT_NE(r.message.find("; at lambda = 4: Newton: "), std::string::npos) << r.message;
  EXPECT_TRUE(r.points[1].failure.empty());
}

TEST(SteppedSweep, AFailedPointCarriesTheArcLengthFallbacksReason) {
  // x² = λ has no solution at λ = −1: the fallback from λ = 1 turns at the fold λ = 0 and goes
  // back to the end of the range behind it, never reaching −1; its own message is kept.
  const FunctionSystem sys = parabola();
  const std::vector<double> lambdas{4.0, 1.0, -1.0};
  const ContinuationResult r = stepped_sweep(sys, VectorXd{{3.0}}, lambdas, SteppedSweepOptions{});
  ASSERT_EQ(r.points.size(), 3u);
  ASSERT_FALSE(r.points[2].newton.converged());
  EXPECT_NE(r.points[2].failure.find("arc-length fallback: "), std::string::npos)
      << r.points[2].failure;
  EXPECT_GT(r.points[2].failure.size(), std::string("arc-length fallback: ").size() + 20);
  EXPECT_NE(r.message.find("at lambda = -1: Newton: "), std::string::npos) << r.message;
}

TEST(SteppedSweep, ReportsAPointWithoutSolutionAndContinuesFromTheLastGoodOne) {
  const FunctionSystem sys = parabola();
  const std::vector<double> lambdas{4.0, 1.0, -1.0, 1.0, 4.0};
  const ContinuationResult r = stepped_sweep(sys, VectorXd{{3.0}}, lambdas, SteppedSweepOptions{});
  EXPECT_FALSE(r.completed);
  ASSERT_EQ(r.points.size(), lambdas.size());
  for (std::size_t i = 0; i < lambdas.size(); ++i) {
    EXPECT_EQ(r.points[i].lambda, lambdas[i]);
    if (lambdas[i] < 0) {
      EXPECT_FALSE(r.points[i].newton.converged());
    } else {
      ASSERT_TRUE(r.points[i].newton.converged()) << i << ": " << r.points[i].newton.message;
      EXPECT_NEAR(r.points[i].x(0), std::sqrt(lambdas[i]), kRootTolerance);
    }
  }
  EXPECT_NE(r.message.find("4 of 5"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("lambda = -1"), std::string::npos) << r.message;

  // No converged point yet: each λ is tried from x0.
  const std::vector<double> first_fails{-1.0, 4.0};
  const ContinuationResult q = stepped_sweep(sys, VectorXd{{3.0}}, first_fails, {});
  ASSERT_EQ(q.points.size(), 2u);
  EXPECT_FALSE(q.points[0].newton.converged());
  ASSERT_TRUE(q.points[1].newton.converged());
  EXPECT_NEAR(q.points[1].x(0), 2.0, kRootTolerance);
}

TEST(SteppedSweep, ReportsProgressOncePerRequestedPoint) {
  const FunctionSystem sys = parabola();
  const std::vector<double> lambdas{4.0, 1.0, -1.0, 1.0};
  std::vector<ContinuationProgress> seen;
  SteppedSweepOptions options;
  options.on_point = [&](const ContinuationProgress& p) { seen.push_back(p); };
  const ContinuationResult r = stepped_sweep(sys, VectorXd{{3.0}}, lambdas, options);
  ASSERT_EQ(seen.size(), lambdas.size());
  for (std::size_t i = 0; i < lambdas.size(); ++i) {
    EXPECT_EQ(seen[i].points, static_cast<int>(i + 1));
    EXPECT_EQ(seen[i].lambda, lambdas[i]);
    EXPECT_DOUBLE_EQ(seen[i].fraction, (i + 1.0) / lambdas.size());
    EXPECT_EQ(seen[i].converged, r.points[i].newton.converged());
  }
  EXPECT_FALSE(seen[2].converged);  // no real root at λ = -1: reported, not hidden
}

TEST(SteppedSweep, InvalidInputThrowsNamingTheField) {
  using testing::expect_invalid_input_naming;
  const FunctionSystem sys = parabola();
  const std::vector<double> lambdas{1.0};
  SteppedSweepOptions o;
  o.max_step_halvings = -1;
  expect_invalid_input_naming([&] { stepped_sweep(sys, VectorXd{{1.0}}, lambdas, o); },
                              "SteppedSweepOptions.max_step_halvings");
  o = {};
  o.newton.tolerance = -1;
  expect_invalid_input_naming([&] { validate(o); }, "SteppedSweepOptions.newton.tolerance");
  o = {};
  EXPECT_THROW(stepped_sweep(sys, VectorXd{{1.0, 2.0}}, lambdas, o), InvalidInput);
  EXPECT_THROW(stepped_sweep(sys, VectorXd{{1.0}}, std::vector<double>{}, o), InvalidInput);
  const std::vector<double> nan{std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW(stepped_sweep(sys, VectorXd{{1.0}}, nan, o), InvalidInput);
}

}  // namespace
}  // namespace stickslip
