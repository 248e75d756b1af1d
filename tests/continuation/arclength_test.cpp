#include "continuation/arclength.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "test_systems.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using testing::FunctionSystem;

// S-curve x³ − x − λ = 0, written in scaled units x = x_unit ξ, λ = λ0 + λ_unit η with
// R = r_unit (ξ³ − ξ − η): folds at ξ = ±1/√3, η = ∓2/(3√3); one root for |η| > 2/(3√3).
FunctionSystem s_curve(double x_unit = 1, double lambda0 = 0, double lambda_unit = 1,
                       double r_unit = 1) {
  return FunctionSystem(
      1,
      [=](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        const double xi = x(0) / x_unit, eta = (l - lambda0) / lambda_unit;
        R(0) = r_unit * (xi * xi * xi - xi - eta);
        if (J) (*J)(0, 0) = r_unit * (3 * xi * xi - 1) / x_unit;
        if (Rl) (*Rl)(0) = -r_unit / lambda_unit;
      },
      r_unit);
}

const double kFoldLambda = 2 / (3 * std::sqrt(3.0));
// Real root of ξ³ − ξ − 1 = 0 (the plastic number), and −ρ of ξ³ − ξ + 1 = 0.
constexpr double kPlasticNumber = 1.324717957244746;
// Converged points satisfy |R| <= tolerance · scale (the corrector's ||F|| bounds ||R||).
constexpr double kNewtonTolerance = 1e-8;
// |Δξ| for a Newton residual 1e-8 at |dR/dξ| >= 2 (away from the folds, where the end points are).
constexpr double kRootTolerance = 1e-8;

int count_reversals(const std::vector<double>& lambda) {
  int reversals = 0;
  double last_sign = 0;
  for (std::size_t i = 1; i < lambda.size(); ++i) {
    const double d = lambda[i] - lambda[i - 1];
    const double sign = d > 0 ? 1 : (d < 0 ? -1 : 0);
    if (sign != 0 && last_sign != 0 && sign != last_sign) ++reversals;
    if (sign != 0) last_sign = sign;
  }
  return reversals;
}

ArcLengthOptions s_curve_options(double lambda_start, double lambda_end) {
  ArcLengthOptions o;
  o.lambda_start = lambda_start;
  o.lambda_end = lambda_end;
  o.initial_step = 0.02;
  o.min_step = 1e-6;
  o.max_step = 0.05;
  return o;
}

// Runs the S-curve in the given units and checks the closed-form properties in ξ, η.
void check_s_curve(double x_unit, double lambda0, double lambda_unit, double r_unit, bool upwards) {
  SCOPED_TRACE(::testing::Message() << "x_unit " << x_unit << " lambda_unit " << lambda_unit
                                    << (upwards ? " up" : " down"));
  const FunctionSystem sys = s_curve(x_unit, lambda0, lambda_unit, r_unit);
  const double sign = upwards ? 1 : -1;
  ArcLengthOptions o = s_curve_options(lambda0 - sign * lambda_unit, lambda0 + sign * lambda_unit);
  o.initial_step *= lambda_unit;
  o.min_step *= lambda_unit;
  o.max_step *= lambda_unit;
  const ContinuationResult r = arclength_continuation(sys, VectorXd{{-sign * 1.3 * x_unit}}, o);
  ASSERT_TRUE(r.completed) << r.message;
  ASSERT_GT(r.points.size(), 10u);
  EXPECT_NE(r.message.find("reached lambda_end"), std::string::npos) << r.message;

  std::vector<double> xi, eta;
  for (const ContinuationPoint& p : r.points) {
    ASSERT_TRUE(p.newton.converged());
    xi.push_back(p.x(0) / x_unit);
    eta.push_back((p.lambda - lambda0) / lambda_unit);
    EXPECT_LE(std::abs(xi.back() * xi.back() * xi.back() - xi.back() - eta.back()),
              kNewtonTolerance)
        << "eta " << eta.back();
  }
  // End points: exactly at lambda_start and lambda_end, on the closed-form roots.
  EXPECT_EQ(r.points.front().lambda, o.lambda_start);
  EXPECT_EQ(r.points.back().lambda, o.lambda_end);
  EXPECT_NEAR(xi.front(), -sign * kPlasticNumber, kRootTolerance);
  EXPECT_NEAR(xi.back(), sign * kPlasticNumber, kRootTolerance);

  // Both folds traversed: λ reverses twice and reaches the fold values (to within the step:
  // near a fold η − η_fold = O(Δξ²) with Δξ <= 0.05 · x_scale / lambda_scale ≈ 0.033).
  EXPECT_EQ(count_reversals(eta), 2);
  constexpr double kFoldResolution = 5e-3;
  // The interior extrema of the path are the folds (its ends are at η = ±1).
  double fold_high = -10, fold_low = 10;
  for (std::size_t i = 1; i + 1 < eta.size(); ++i) {
    const bool local_max = eta[i] >= eta[i - 1] && eta[i] >= eta[i + 1];
    const bool local_min = eta[i] <= eta[i - 1] && eta[i] <= eta[i + 1];
    if (local_max) fold_high = std::max(fold_high, eta[i]);
    if (local_min) fold_low = std::min(fold_low, eta[i]);
  }
  EXPECT_LE(fold_high, kFoldLambda + 1e-9);
  EXPECT_GE(fold_high, kFoldLambda - kFoldResolution);
  EXPECT_GE(fold_low, -kFoldLambda - 1e-9);
  EXPECT_LE(fold_low, -kFoldLambda + kFoldResolution);

  // No branch lost: the curve is a graph over ξ, so the path must sweep ξ monotonically, in steps
  // bounded by the arc length: |Δξ| <= Δs · x_scale / lambda_scale / x_unit (x_scale = ||x_first||
  // = ρ x_unit, lambda_scale = 2 λ_unit); a factor 2 for the chord vs the pseudo arc length.
  const double max_jump = 2 * 0.05 * kPlasticNumber / 2;
  for (std::size_t i = 1; i < xi.size(); ++i) {
    const double d = sign * (xi[i] - xi[i - 1]);
    EXPECT_GT(d, 0) << "at point " << i;
    EXPECT_LE(d, max_jump) << "at point " << i;
  }
}

TEST(ArcLength, SCurveTraversesBothFoldsWithoutLosingTheBranch) {
  check_s_curve(1, 0, 1, 1, true);
  check_s_curve(1, 0, 1, 1, false);
}

TEST(ArcLength, SCurveInPhysicalUnitsNeedsNoManualScaling) {
  // x ~ 1e-6 m, λ ~ 1e4 rad/s, R ~ 1e2 N: the automatic scaling makes it the same problem.
  check_s_curve(1e-6, 1e4, 1e3, 1e2, true);
}

TEST(ArcLength, StepGuardsResolveFoldsEvenWithHugeSteps) {
  // max_step = the whole λ range: without the tangent-angle and correction-distance limits the
  // steps hop across the folds (the path's extreme λ would be ~0.1 instead of ±0.385). Each
  // guard alone must prevent it (3.1 rad and 1e9 switch a guard off).
  const FunctionSystem sys = s_curve();
  const std::pair<double, double> guards[] = {{0.5, 1e9}, {3.1, 1.0}};
  for (const auto& [max_turn_angle, max_correction] : guards) {
    for (double max_step : {1.0, 2.0}) {
      SCOPED_TRACE(::testing::Message() << "max_turn_angle " << max_turn_angle << " max_correction "
                                        << max_correction << " max_step " << max_step);
      ArcLengthOptions o = s_curve_options(-1, 1);
      o.initial_step = 0.5;
      o.max_step = max_step;
      o.max_turn_angle = max_turn_angle;
      o.max_correction = max_correction;
      const ContinuationResult r = arclength_continuation(sys, VectorXd{{-1.3}}, o);
      ASSERT_TRUE(r.completed) << r.message;
      double lambda_max_lower = -10, lambda_min_upper = 10;
      std::vector<double> lambda;
      for (const ContinuationPoint& p : r.points) {
        const double l = p.lambda, x = p.x(0);
        lambda.push_back(l);
        EXPECT_LE(std::abs(x * x * x - x - l), kNewtonTolerance);
        if (x < 0) lambda_max_lower = std::max(lambda_max_lower, l);  // the fold at x = −1/√3
        if (x > 0) lambda_min_upper = std::min(lambda_min_upper, l);  // the fold at x = +1/√3
      }
      EXPECT_EQ(count_reversals(lambda), 2);
      // A step that overshoots a fold by more than ~one step's sagitta is rejected.
      constexpr double kCoarseFoldResolution = 0.03;
      EXPECT_NEAR(lambda_max_lower, kFoldLambda, kCoarseFoldResolution);
      EXPECT_NEAR(lambda_min_upper, -kFoldLambda, kCoarseFoldResolution);
    }
  }
}

TEST(ArcLength, StopsAtMaxPoints) {
  const FunctionSystem sys = s_curve();
  ArcLengthOptions o = s_curve_options(-1, 1);
  o.max_points = 5;
  const ContinuationResult r = arclength_continuation(sys, VectorXd{{-1.3}}, o);
  EXPECT_FALSE(r.completed);
  EXPECT_EQ(r.points.size(), 5u);
  EXPECT_NE(r.message.find("max_points"), std::string::npos) << r.message;
}

TEST(ArcLength, ReportsProgressForEveryReturnedPoint) {
  const FunctionSystem sys = s_curve();
  ArcLengthOptions o = s_curve_options(-1, 1);
  std::vector<ContinuationProgress> seen;
  o.on_point = [&](const ContinuationProgress& p) { seen.push_back(p); };
  const ContinuationResult r = arclength_continuation(sys, VectorXd{{-1.3}}, o);
  ASSERT_TRUE(r.completed) << r.message;
  ASSERT_EQ(seen.size(), r.points.size());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].points, static_cast<int>(i + 1));
    EXPECT_EQ(seen[i].lambda, r.points[i].lambda);
    EXPECT_DOUBLE_EQ(seen[i].fraction, std::clamp((r.points[i].lambda + 1) / 2, 0.0, 1.0));
  }
  EXPECT_EQ(seen.front().fraction, 0.0);
  EXPECT_EQ(seen.back().fraction, 1.0);
}

TEST(ArcLength, ReportsAStepBelowMinStep) {
  // x − λ = 0, but R is NaN for λ > 0.5: the corrector fails there until the step is too small.
  const FunctionSystem sys(
      1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        const double nan = l > 0.5 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
        R(0) = x(0) - l + nan;
        if (J) (*J)(0, 0) = 1;
        if (Rl) (*Rl)(0) = -1;
      });
  ArcLengthOptions o = s_curve_options(0, 1);
  o.min_step = 1e-3;
  const ContinuationResult r = arclength_continuation(sys, VectorXd{{0.0}}, o);
  EXPECT_FALSE(r.completed);
  EXPECT_NE(r.message.find("min_step"), std::string::npos) << r.message;
  ASSERT_GT(r.points.size(), 3u);
  for (const ContinuationPoint& p : r.points) {
    EXPECT_TRUE(p.newton.converged());
    EXPECT_LE(p.lambda, 0.5);
    EXPECT_NEAR(p.x(0), p.lambda, kRootTolerance);
  }
  // It got within a couple of min_steps (arc length √2 per unit of λ here: x_scale = 1,
  // lambda_scale = 1) of the wall.
  EXPECT_GT(r.points.back().lambda, 0.5 - 4 * o.min_step);
}

TEST(ArcLength, ReportsABranchThatTurnsBackPastLambdaStart) {
  // Circle x² + λ² = 1 from (x, λ) = (1, 0) towards λ = 2: fold at λ = 1, back to (−1, 0).
  const FunctionSystem circle(
      1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        R(0) = x(0) * x(0) + l * l - 1;
        if (J) (*J)(0, 0) = 2 * x(0);
        if (Rl) (*Rl)(0) = 2 * l;
      });
  testing::expect_jacobians_match_finite_differences(circle, VectorXd{{0.6}}, 0.3);
  ArcLengthOptions o = s_curve_options(0, 2);
  const ContinuationResult r = arclength_continuation(circle, VectorXd{{1.1}}, o);
  EXPECT_FALSE(r.completed);
  EXPECT_NE(r.message.find("lambda_start"), std::string::npos) << r.message;
  for (const ContinuationPoint& p : r.points) {
    EXPECT_LE(std::abs(p.x(0) * p.x(0) + p.lambda * p.lambda - 1), kNewtonTolerance);
  }
  EXPECT_NEAR(r.points.front().x(0), 1.0, kRootTolerance);
  EXPECT_EQ(r.points.back().lambda, 0.0);
  EXPECT_NEAR(r.points.back().x(0), -1.0, kRootTolerance);
  EXPECT_EQ(count_reversals([&] {
              std::vector<double> l;
              for (const auto& p : r.points) l.push_back(p.lambda);
              return l;
            }()),
            1);
}

TEST(ArcLength, FailedFirstPointIsReported) {
  const FunctionSystem sys(1,
                           [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
                             R(0) = x(0) * x(0) + 1 + l;  // no real root for λ > −1
                             if (J) (*J)(0, 0) = 2 * x(0);
                             if (Rl) (*Rl)(0) = 1;
                           });
  const ContinuationResult r = arclength_continuation(sys, VectorXd{{1.0}}, s_curve_options(0, 1));
  EXPECT_FALSE(r.completed);
  ASSERT_EQ(r.points.size(), 1u);
  EXPECT_FALSE(r.points[0].newton.converged());
  EXPECT_NE(r.message.find("lambda_start"), std::string::npos) << r.message;
}

TEST(ArcLength, InvalidOptionsThrowNamingTheField) {
  using testing::expect_invalid_input_naming;
  auto with = [](auto change) {
    ArcLengthOptions o = s_curve_options(0, 1);
    change(o);
    return [o] { validate(o); };
  };
  EXPECT_NO_THROW(validate(s_curve_options(0, 1)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_invalid_input_naming(with([&](ArcLengthOptions& o) { o.lambda_start = nan; }),
                              "ArcLengthOptions.lambda_start");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.lambda_end = 0; }),
                              "ArcLengthOptions.lambda_end");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.min_step = 0; }),
                              "ArcLengthOptions.min_step");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.max_step = 1e-7; }),
                              "ArcLengthOptions.max_step");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.initial_step = 1; }),
                              "ArcLengthOptions.initial_step");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.max_points = 1; }),
                              "ArcLengthOptions.max_points");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.target_newton_iterations = 0; }),
                              "ArcLengthOptions.target_newton_iterations");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.newton.max_iterations = 0; }),
                              "ArcLengthOptions.newton.max_iterations");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.x_scale = -1; }),
                              "ArcLengthOptions.x_scale");
  expect_invalid_input_naming(with([&](ArcLengthOptions& o) { o.lambda_scale = nan; }),
                              "ArcLengthOptions.lambda_scale");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.max_turn_angle = 4; }),
                              "ArcLengthOptions.max_turn_angle");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.max_correction = 0; }),
                              "ArcLengthOptions.max_correction");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.lambda_return_limit = 0.5; }),
                              "ArcLengthOptions.lambda_return_limit");
  expect_invalid_input_naming(with([](ArcLengthOptions& o) { o.step_growth = 0.5; }),
                              "ArcLengthOptions.step_growth");
  // Defaults (zero steps) are not a valid configuration: steps must be chosen.
  expect_invalid_input_naming([] { validate(ArcLengthOptions{}); }, "ArcLengthOptions.");
  const FunctionSystem sys = s_curve();
  EXPECT_THROW(arclength_continuation(sys, VectorXd{{1.0, 2.0}}, s_curve_options(0, 1)),
               InvalidInput);
}

// ---------- Corners of piecewise-smooth curves (friction contact sampled in time). ----------

TEST(ArcLength, FollowsACornerOfAPiecewiseLinearCurve) {
  // x = g(λ), g = 0 for λ < 0.3 and 3 (λ − 0.3) beyond: the tangent turns by atan 3 = 1.25 rad >
  // max_turn_angle at the corner however small the step, and must be accepted as a corner there.
  const FunctionSystem kinked(
      1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        const bool beyond = l >= 0.3;
        R(0) = x(0) - (beyond ? 3 * (l - 0.3) : 0.0);
        if (J) (*J)(0, 0) = 1;
        if (Rl) (*Rl)(0) = beyond ? -3 : 0;
      });
  const ContinuationResult r =
      arclength_continuation(kinked, VectorXd{{0.0}}, s_curve_options(0, 1));
  ASSERT_TRUE(r.completed) << r.message;
  std::vector<double> lambda;
  for (const ContinuationPoint& p : r.points) {
    lambda.push_back(p.lambda);
    EXPECT_NEAR(p.x(0), p.lambda >= 0.3 ? 3 * (p.lambda - 0.3) : 0.0, kRootTolerance);
  }
  EXPECT_EQ(count_reversals(lambda), 0);
  EXPECT_EQ(r.points.back().lambda, 1.0);
}

TEST(ArcLength, FollowsACornerFold) {
  // λ = (1 − |x|)/2: a fold at a corner (x = 0, λ = 1/2; turn 2 atan(1/2) = 0.93 rad). From x = −1
  // (λ = 0) towards λ = 1 the path must go over the corner and back down to λ = 0 at x = +1.
  const FunctionSystem vee(1,
                           [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
                             R(0) = l - 0.5 * (1 - std::abs(x(0)));
                             if (J) (*J)(0, 0) = x(0) >= 0 ? 0.5 : -0.5;
                             if (Rl) (*Rl)(0) = 1;
                           });
  const ContinuationResult r = arclength_continuation(vee, VectorXd{{-1.0}}, s_curve_options(0, 1));
  EXPECT_FALSE(r.completed);
  EXPECT_NE(r.message.find("turned back past lambda_start"), std::string::npos) << r.message;
  std::vector<double> lambda;
  double lambda_max = -1;
  for (const ContinuationPoint& p : r.points) {
    lambda.push_back(p.lambda);
    lambda_max = std::max(lambda_max, p.lambda);
    EXPECT_NEAR(p.lambda, 0.5 * (1 - std::abs(p.x(0))), kRootTolerance);
  }
  EXPECT_EQ(count_reversals(lambda), 1);
  EXPECT_NEAR(lambda_max, 0.5, 0.05);  // within a step (max_step 0.05) of the corner
  EXPECT_NEAR(r.points.back().x(0), 1.0, kRootTolerance);
}

// ---------- Step control by curvature (target_turn_angle, max_lambda_step). ----------

// The forced response of a linear oscillator, m ẍ + c ẋ + k x = F cos λt, in the coefficients of
// x = a cos λt + b sin λt: R = [(k − mλ²) a + cλ b − F; (k − mλ²) b − cλ a]. Closed form:
// |x| = F / √D(λ), D = (k − mλ²)² + (cλ)², largest where dD/d(λ²) = 0: D* = c²k/m − c⁴/(4m²).
// From λ = 0.5 the first point's amplitude is 1/75 of the peak (Q = 100), so in the continuation's
// scaled variables the resonance is a spike 75 units high: with the arc-length step bounded by
// max_step in λ units (the old control) the flanks take hundreds of points.
TEST(ArcLength, CurvatureControlTakesLongStepsOnStraightFlanksAndShortOnesAtThePeak) {
  const double m = 1, k = 1, c = 0.01, F = 1;
  const FunctionSystem oscillator(
      2, [=](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        const double d = k - m * l * l;
        R(0) = d * x(0) + c * l * x(1) - F;
        R(1) = d * x(1) - c * l * x(0);
        if (J) *J << d, c * l, -c * l, d;
        if (Rl) (*Rl) << -2 * m * l * x(0) + c * x(1), -2 * m * l * x(1) - c * x(0);
      });
  const double peak = F / std::sqrt(c * c * k / m - std::pow(c, 4) / (4 * m * m));
  const auto amplitude = [&](double l) { return F / std::hypot(k - m * l * l, c * l); };
  ArcLengthOptions o;
  o.lambda_start = 0.5;
  o.lambda_end = 2;
  o.initial_step = 0.01;
  o.min_step = 1e-7;
  o.max_step = 0.075;  // range / 20
  const VectorXd x0{{F / (k - m * 0.25), 0.0}};
  const ContinuationResult old_control = arclength_continuation(oscillator, x0, o);
  ArcLengthOptions curvature = o;
  curvature.max_lambda_step = o.max_step;
  curvature.max_step = 1e3;
  curvature.target_turn_angle = 0.1;
  const ContinuationResult r = arclength_continuation(oscillator, x0, curvature);
  ASSERT_TRUE(old_control.completed) << old_control.message;
  ASSERT_TRUE(r.completed) << r.message;
  EXPECT_LT(3 * r.points.size(), old_control.points.size())
      << r.points.size() << " vs " << old_control.points.size();
  double largest = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const ContinuationPoint& p = r.points[i];
    EXPECT_NEAR(p.x.norm(), amplitude(p.lambda), 1e-7 * peak);
    largest = std::max(largest, p.x.norm());
    if (i > 0) {  // λ never advances by more than 1.25 max_lambda_step (arclength.h)
      EXPECT_LE(std::abs(p.lambda - r.points[i - 1].lambda),
                1.25 * curvature.max_lambda_step * (1 + 1e-12));
    }
    if (i > 1 && p.tangent.size() == 3) {  // (the clipped last point carries no tangent)
      // Each step turns the tangent by about the target, never by much more.
      EXPECT_LT(std::acos(std::clamp(p.tangent.dot(r.points[i - 1].tangent), -1.0, 1.0)),
                3 * curvature.target_turn_angle);
    }
  }
  // The peak is sampled where the curve bends most: the largest point within 1e-3 of the
  // closed-form peak.
  EXPECT_GT(largest, (1 - 1e-3) * peak);
  EXPECT_LE(largest, peak * (1 + 1e-9));
}

// Folds located by bisection on the tangent's λ-component (bisect_on_arc) against the closed form
// of the S-curve: ξ = ∓1/√3, η = ±2/(3√3). Scaled as the continuation scaled (x_scale = ||x_0||,
// lambda_scale = 2): the located point is within the final bracket of the exact fold in λ and in
// x (arclength.h), and the linear interpolation of the smooth test function makes it far closer.
TEST(ArcLength, BisectionOnTheTangentLocatesBothFoldsOfTheSCurve) {
  const FunctionSystem sys = s_curve();
  const ContinuationResult r =
      arclength_continuation(sys, VectorXd{{-1.3}}, s_curve_options(-1, 1));
  ASSERT_TRUE(r.completed) << r.message;
  EXPECT_EQ(r.lambda_scale, 2.0);
  EXPECT_NEAR(r.x_scale, kPlasticNumber, 1e-8);
  ArcBisectionOptions o;
  o.tolerance = 1e-9;
  o.x_scale = r.x_scale;
  o.lambda_scale = r.lambda_scale;
  o.newton.tolerance = 1e-13;
  const auto g = [](const ContinuationPoint& p) { return p.tangent(1); };
  int folds = 0;
  for (size_t i = 0; i + 1 < r.points.size(); ++i) {
    const ContinuationPoint &a = r.points[i], &b = r.points[i + 1];
    ASSERT_EQ(a.tangent.size(), 2);
    if (b.tangent.size() != 2 || a.tangent(1) * b.tangent(1) >= 0) continue;
    const ArcBisectionResult f = bisect_on_arc(sys, a, a.tangent(1), b, b.tangent(1), g, o);
    ASSERT_TRUE(f.located) << f.message;
    EXPECT_LE(f.bracket, o.tolerance);
    // Upwards from ξ = −ρ: first the fold at ξ = −1/√3, η = +2/(3√3), then the other.
    const double xi = folds == 0 ? -1 / std::sqrt(3.0) : 1 / std::sqrt(3.0);
    const double eta = folds == 0 ? kFoldLambda : -kFoldLambda;
    // |Δλ| <= bracket; |Δx| <= bracket · x_scale / lambda_scale; plus the corrector's 1e-13.
    EXPECT_NEAR(f.point.lambda, eta, o.tolerance) << "fold " << folds;
    EXPECT_NEAR(f.point.x(0), xi, o.tolerance * r.x_scale / r.lambda_scale + 1e-12);
    EXPECT_LE(std::abs(f.g), 1e-6);
    EXPECT_GT(f.solves, 10);
    ++folds;
  }
  EXPECT_EQ(folds, 2);
  // No sign change: refused.
  EXPECT_THROW(bisect_on_arc(sys, r.points[0], 1.0, r.points[1], 2.0, g, o), InvalidInput);
  o.tolerance = 0;
  EXPECT_THROW(bisect_on_arc(sys, r.points[0], 1.0, r.points[1], -1.0, g, o), InvalidInput);
}

}  // namespace
}  // namespace stickslip
