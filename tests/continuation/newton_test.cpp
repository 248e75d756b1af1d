#include "continuation/newton.h"

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

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Circle x0² + x1² = 4 meets hyperbola x0 x1 = 1: closed form x0² = 2 + √3, x1 = 1/x0.
FunctionSystem circle_hyperbola() {
  return FunctionSystem(2, [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
    R << x(0) * x(0) + x(1) * x(1) - 4, x(0) * x(1) - 1;
    if (J) *J << 2 * x(0), 2 * x(1), x(1), x(0);
    if (Rl) Rl->setZero();
  });
}

// circle_hyperbola() counting its evaluations: with dR/dx (jacobians) and of R alone (residuals).
FunctionSystem counted_circle_hyperbola(int& residuals, int& jacobians) {
  const FunctionSystem plain = circle_hyperbola();
  return FunctionSystem(2, [&, plain](const VectorXd& x, double l, VectorXd& R, MatrixXd* J,
                                      VectorXd* Rl) {
    ++(J ? jacobians : residuals);
    plain.evaluate(x, l, R, J, Rl);
  });
}

// atan(x − λ): the full Newton step overshoots (and diverges) when |x − λ| > 1.3917.
FunctionSystem shifted_atan() {
  return FunctionSystem(1, [](const VectorXd& x, double l, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
    const double e = x(0) - l;
    R(0) = std::atan(e);
    if (J) (*J)(0, 0) = 1 / (1 + e * e);
    if (Rl) (*Rl)(0) = -1 / (1 + e * e);
  });
}

TEST(Newton, TestSystemJacobiansMatchFiniteDifferences) {
  testing::expect_jacobians_match_finite_differences(circle_hyperbola(), VectorXd{{1.3, -0.4}},
                                                     0.0);
  testing::expect_jacobians_match_finite_differences(shifted_atan(), VectorXd{{0.7}}, 0.2);
}

TEST(Newton, ConvergesQuadraticallyToTheClosedFormRoot) {
  const FunctionSystem sys = circle_hyperbola();
  VectorXd x{{3.0, 1.0}};
  NewtonOptions options;
  options.tolerance = 1e-14;  // iterate down to round-off to see the asymptotic rate
  options.reuse_jacobian = false;  // the textbook iteration (chord steps: the test below)
  const NewtonSummary s = solve_newton(sys, 0.0, x, options);
  ASSERT_TRUE(s.converged()) << s.message;
  const double x0 = std::sqrt(2 + std::sqrt(3.0));
  // Root conditioning: |J⁻¹| = O(1), residual 1e-14 → error O(1e-14).
  constexpr double kRootTolerance = 1e-12;
  EXPECT_NEAR(x(0), x0, kRootTolerance);
  EXPECT_NEAR(x(1), 1 / x0, kRootTolerance);
  ASSERT_EQ(static_cast<int>(s.residual_history.size()), s.iterations + 1);
  EXPECT_DOUBLE_EQ(s.residual_history.back(), s.residual_norm);

  // Order estimate p = log(r_{k+1}/r_k) / log(r_k/r_{k−1}) on the asymptotic part of the history
  // (r_{k−1} < 0.1) above round-off (r_{k+1} > 1e-13): 2 for Newton, 1 for a linear method.
  constexpr double kAsymptotic = 0.1, kRoundoff = 1e-13, kMinOrder = 1.8;
  const auto& r = s.residual_history;
  int checked = 0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k) {
    if (r[k - 1] < kAsymptotic && r[k + 1] > kRoundoff) {
      const double p = std::log(r[k + 1] / r[k]) / std::log(r[k] / r[k - 1]);
      EXPECT_GT(p, kMinOrder) << "at iteration " << k;
      ++checked;
    }
  }
  EXPECT_GE(checked, 1) << "history too short to measure the rate";
}

TEST(Newton, DampingConvergesWhereTheFullStepOvershoots) {
  const FunctionSystem sys = shifted_atan();
  // Monotone line search only (no watchdog steps).
  NewtonOptions monotone;
  monotone.watchdog_steps = 0;
  VectorXd x{{3.0}};
  const NewtonSummary s = solve_newton(sys, 0.0, x, monotone);
  ASSERT_TRUE(s.converged()) << s.message;
  EXPECT_NEAR(x(0), 0.0, 1e-8);  // atan'(0) = 1: |x| = |R| <= tolerance
  EXPECT_LE(s.residual_norm, 1e-8);
  // Residuals decrease monotonically (sufficient decrease at every accepted step).
  for (std::size_t k = 1; k < s.residual_history.size(); ++k) {
    EXPECT_LT(s.residual_history[k], s.residual_history[k - 1]);
  }
  // With the default watchdog the relaxed full steps diverge (|R| -> π/2), the solver returns to
  // the best iterate and backtracks: it converges too.
  VectorXd w{{3.0}};
  const NewtonSummary sw = solve_newton(sys, 0.0, w, NewtonOptions{});
  ASSERT_TRUE(sw.converged()) << sw.message;
  EXPECT_NEAR(w(0), 0.0, 1e-8);

  // Plain Newton (no backtracking, no watchdog) from the same guess: the full step increases |R|.
  NewtonOptions plain;
  plain.min_step_fraction = 1.0;
  plain.watchdog_steps = 0;
  VectorXd y{{3.0}};
  const NewtonSummary f = solve_newton(sys, 0.0, y, plain);
  EXPECT_EQ(f.termination, NewtonTermination::kLineSearchFailed) << f.message;
  EXPECT_FALSE(f.converged());
  EXPECT_EQ(f.iterations, 0);
  EXPECT_EQ(y(0), 3.0);  // the last accepted iterate is returned
}

TEST(Newton, TrialJacobianOptionChangesOnlyWhereTheJacobiansAreEvaluated) {
  // Both settings take the same steps (bitwise: the same LU of the same dR/dx at the same
  // iterates); without trial Jacobians dR/dx is evaluated once per step taken (at the guess and at
  // every accepted iterate that is not yet converged) and never at the solution.
  int residuals = 0, jacobians = 0;
  const FunctionSystem counted = counted_circle_hyperbola(residuals, jacobians);
  NewtonOptions eager, lazy;
  eager.trial_jacobian = true;
  lazy.reuse_jacobian = false;
  VectorXd x_eager{{3.0, 1.0}}, x_lazy{{3.0, 1.0}};
  const NewtonSummary e = solve_newton(counted, 0.0, x_eager, eager);
  const int eager_jacobians = jacobians, eager_residuals = residuals;
  residuals = jacobians = 0;
  const NewtonSummary l = solve_newton(counted, 0.0, x_lazy, lazy);
  ASSERT_TRUE(e.converged() && l.converged());
  EXPECT_EQ(x_eager, x_lazy);
  EXPECT_EQ(e.residual_history, l.residual_history);
  ASSERT_GE(l.iterations, 3);
  EXPECT_EQ(eager_jacobians, e.iterations + 1);  // the guess and every trial
  EXPECT_EQ(eager_residuals, 0);
  EXPECT_EQ(jacobians, l.iterations);  // the guess and the unconverged iterates
  EXPECT_EQ(residuals, l.iterations);  // every trial
}

TEST(Newton, ChordStepsReachTheSameRootWithFewerJacobians) {
  // Textbook Newton and Newton with chord steps from the same guess: the same root (closed form),
  // every chord step (an accepted step without a new dR/dx) contracts ||R|| at least tenfold, and
  // fewer Jacobians are evaluated than steps are taken.
  int residuals = 0, jacobians = 0;
  const FunctionSystem counted = counted_circle_hyperbola(residuals, jacobians);
  NewtonOptions textbook, chord;
  textbook.tolerance = chord.tolerance = 1e-12;
  textbook.reuse_jacobian = false;
  ASSERT_TRUE(chord.reuse_jacobian);  // the default
  VectorXd xt{{3.0, 1.0}}, xc{{3.0, 1.0}};
  const NewtonSummary t = solve_newton(counted, 0.0, xt, textbook);
  const int textbook_jacobians = jacobians;
  residuals = jacobians = 0;
  const NewtonSummary c = solve_newton(counted, 0.0, xc, chord);
  ASSERT_TRUE(t.converged() && c.converged());
  const double x0 = std::sqrt(2 + std::sqrt(3.0));
  constexpr double kRootTolerance = 1e-10;  // residual 1e-12, |J⁻¹| = O(1)
  EXPECT_NEAR(xc(0), x0, kRootTolerance);
  EXPECT_NEAR(xc(1), 1 / x0, kRootTolerance);
  EXPECT_EQ(textbook_jacobians, t.iterations);
  EXPECT_LT(jacobians, c.iterations);  // some steps were chord steps
  const int chord_steps = c.iterations - jacobians;
  // The chord steps are the last ones (once ||R|| falls tenfold per step it keeps doing so here):
  // each of them contracts ||R|| tenfold.
  const std::vector<double>& h = c.residual_history;
  for (int k = c.iterations - chord_steps; k < c.iterations; ++k) {
    EXPECT_LE(h[k + 1], 0.1 * h[k]) << "step " << k;
  }
}

TEST(Newton, ReportsASingularJacobian) {
  // Two parallel lines: dR/dx = [1 1; 2 2] everywhere.
  const FunctionSystem parallel(
      2, [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        R << x(0) + x(1) - 1, 2 * x(0) + 2 * x(1) - 3;
        if (J) *J << 1, 1, 2, 2;
        if (Rl) Rl->setZero();
      });
  VectorXd x{{0.0, 0.0}};
  NewtonSummary s = solve_newton(parallel, 0.0, x, NewtonOptions{});
  EXPECT_EQ(s.termination, NewtonTermination::kSingularJacobian) << s.message;

  // x² − 1 started at the critical point x = 0.
  const FunctionSystem parabola(
      1, [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        R(0) = x(0) * x(0) - 1;
        if (J) (*J)(0, 0) = 2 * x(0);
        if (Rl) Rl->setZero();
      });
  VectorXd z{{0.0}};
  s = solve_newton(parabola, 0.0, z, NewtonOptions{});
  EXPECT_EQ(s.termination, NewtonTermination::kSingularJacobian) << s.message;
  EXPECT_EQ(s.iterations, 0);
}

TEST(Newton, ReportsNonFiniteValues) {
  const FunctionSystem log_system(
      1, [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        R(0) = std::log(x(0));
        if (J) (*J)(0, 0) = 1 / x(0);
        if (Rl) Rl->setZero();
      });
  VectorXd x{{-1.0}};
  NewtonSummary s = solve_newton(log_system, 0.0, x, NewtonOptions{});
  EXPECT_EQ(s.termination, NewtonTermination::kNonFinite) << s.message;
  EXPECT_TRUE(s.residual_history.empty());

  // From x = 3 the full step lands at x < 0 (NaN): backtracking steps over it to the root x = 1.
  x << 3.0;
  s = solve_newton(log_system, 0.0, x, NewtonOptions{});
  ASSERT_TRUE(s.converged()) << s.message;
  EXPECT_NEAR(x(0), 1.0, 1e-8);

  // Finite R but a NaN Jacobian.
  const FunctionSystem nan_jacobian(
      1, [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        R(0) = x(0) - 1;
        if (J) (*J)(0, 0) = kNaN;
        if (Rl) Rl->setZero();
      });
  x << 0.0;
  s = solve_newton(nan_jacobian, 0.0, x, NewtonOptions{});
  EXPECT_EQ(s.termination, NewtonTermination::kNonFinite) << s.message;
}

TEST(Newton, ConvergenceTestIsRelativeToTheResidualScale) {
  // R = σ (eˣ − 2) with residual_scale σ: the same iterates for every σ, so the same count; the
  // root is ln 2.
  NewtonOptions options;
  int reference_iterations = -1;
  for (double sigma : {1e-3, 1.0, 1e6}) {
    const FunctionSystem sys(
        1,
        [sigma](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
          R(0) = sigma * (std::exp(x(0)) - 2);
          if (J) (*J)(0, 0) = sigma * std::exp(x(0));
          if (Rl) Rl->setZero();
        },
        sigma);
    VectorXd x{{2.0}};
    const NewtonSummary s = solve_newton(sys, 0.0, x, options);
    ASSERT_TRUE(s.converged()) << s.message;
    EXPECT_LE(s.residual_norm, options.tolerance * sigma);
    EXPECT_GT(s.residual_history[s.residual_history.size() - 2], options.tolerance * sigma)
        << "stopped later than needed";
    EXPECT_NEAR(x(0), std::log(2.0), 1e-8);
    if (reference_iterations < 0) reference_iterations = s.iterations;
    EXPECT_EQ(s.iterations, reference_iterations) << "sigma = " << sigma;
  }

  // A loose tolerance·scale stops earlier; a guess that already satisfies it takes 0 iterations.
  const FunctionSystem big(
      1,
      [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        R(0) = std::exp(x(0)) - 2;
        if (J) (*J)(0, 0) = std::exp(x(0));
        if (Rl) Rl->setZero();
      },
      1e6);
  VectorXd x{{2.0}};
  const NewtonSummary s = solve_newton(big, 0.0, x, options);
  EXPECT_TRUE(s.converged());
  EXPECT_LT(s.iterations, reference_iterations);
  EXPECT_GT(s.residual_norm, 1e-8);
  x << 0.69;  // |e^0.69 − 2| ≈ 6e-3 <= 1e-8 · 1e6
  EXPECT_EQ(solve_newton(big, 0.0, x, options).iterations, 0);
}

TEST(Newton, StopsAtMaxIterations) {
  // Double root of x²: Newton converges only linearly (x halves each step).
  const FunctionSystem square(1,
                              [](const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd*) {
                                R(0) = x(0) * x(0);
                                if (J) (*J)(0, 0) = 2 * x(0);
                              });
  NewtonOptions options;
  options.max_iterations = 5;
  VectorXd x{{1.0}};
  const NewtonSummary s = solve_newton(square, 0.0, x, options);
  EXPECT_EQ(s.termination, NewtonTermination::kMaxIterations) << s.message;
  EXPECT_EQ(s.iterations, 5);
  EXPECT_EQ(s.residual_history.size(), 6u);
  EXPECT_DOUBLE_EQ(x(0), 1.0 / 32);
}

TEST(Newton, InvalidInputThrowsNamingTheField) {
  using testing::expect_invalid_input_naming;
  auto with = [](auto change) {
    NewtonOptions o;
    change(o);
    return [o] { validate(o); };
  };
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.tolerance = 0; }),
                              "NewtonOptions.tolerance");
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.tolerance = kNaN; }),
                              "NewtonOptions.tolerance");
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.max_iterations = 0; }),
                              "NewtonOptions.max_iterations");
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.min_step_fraction = 0; }),
                              "NewtonOptions.min_step_fraction");
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.min_step_fraction = 1.5; }),
                              "NewtonOptions.min_step_fraction");
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.min_rcond = -1; }),
                              "NewtonOptions.min_rcond");
  expect_invalid_input_naming(with([](NewtonOptions& o) { o.watchdog_steps = -1; }),
                              "NewtonOptions.watchdog_steps");
  EXPECT_NO_THROW(validate(NewtonOptions{}));

  const FunctionSystem sys = circle_hyperbola();
  VectorXd wrong_size{{1.0, 2.0, 3.0}};
  EXPECT_THROW(solve_newton(sys, 0.0, wrong_size, NewtonOptions{}), InvalidInput);
  const FunctionSystem zero_scale(
      1, [](const VectorXd& x, double, VectorXd& R, MatrixXd*, VectorXd*) { R = x; }, 0.0);
  VectorXd x{{1.0}};
  expect_invalid_input_naming([&] { solve_newton(zero_scale, 0.0, x, NewtonOptions{}); },
                              "residual_scale");
}

}  // namespace
}  // namespace stickslip
