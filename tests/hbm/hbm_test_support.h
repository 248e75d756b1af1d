// Shared checks of the harmonic-balance tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "../derivative_check.h"
#include "hbm/harmonic_balance.h"

namespace stickslip::testing {

// The analytic dR/dx and dR/dΩ of `sys` at (x, omega) against central differences with steps
// x_step (every unknown) and 1e-6 omega; both must agree to `tolerance` relative (Frobenius and
// 2-norm of the derivative). Then the Taylor-remainder slope of both together.
inline void expect_derivatives_match_central_differences(const HarmonicBalanceSystem& sys,
                                                         const Eigen::VectorXd& x, double omega,
                                                         double x_step, double tolerance) {
  Eigen::VectorXd R, dRdw;
  Eigen::MatrixXd J;
  sys.evaluate(x, omega, R, &J, &dRdw);
  Eigen::MatrixXd fd(J.rows(), J.cols());
  for (Eigen::Index q = 0; q < x.size(); ++q) {
    Eigen::VectorXd xp = x, xm = x, Rp, Rm;
    xp[q] += x_step;
    xm[q] -= x_step;
    sys.evaluate(xp, omega, Rp, nullptr, nullptr);
    sys.evaluate(xm, omega, Rm, nullptr, nullptr);
    fd.col(q) = (Rp - Rm) / (2 * x_step);
  }
  EXPECT_LE((fd - J).norm(), tolerance * J.norm());
  const double hw = 1e-6 * omega;
  Eigen::VectorXd Rp, Rm;
  sys.evaluate(x, omega + hw, Rp, nullptr, nullptr);
  sys.evaluate(x, omega - hw, Rm, nullptr, nullptr);
  EXPECT_LE(((Rp - Rm) / (2 * hw) - dRdw).norm(), tolerance * dRdw.norm());
  // And the Taylor slope along a direction mixing every unknown and Ω (derivative_check.h):
  // δx of x's size, δΩ = 1e-2 Ω per unit step.
  Eigen::VectorXd dx(x.size());
  for (Eigen::Index q = 0; q < x.size(); ++q) dx[q] = std::cos(1.0 + 2.7 * static_cast<double>(q));
  dx *= std::max(x.norm(), x_step) / dx.norm();
  testing::expect_taylor_slope(testing::taylor_remainder(sys, x, omega, dx, 1e-2 * omega));
}

// The first pair's cycle at x both slips and separates somewhere: the regimes a derivative check
// at x must cover.
inline void expect_first_pair_slips_and_separates(const HarmonicBalanceSystem& sys,
                                                  const Eigen::VectorXd& x) {
  std::vector<CycleStatistics> stats;
  Eigen::VectorXd F;
  sys.contact_forces(x, F, &stats);
  ASSERT_FALSE(stats.empty());
  EXPECT_GT(stats[0].separation_fraction, 0.0);
  EXPECT_GT(stats[0].slip_fraction, 0.0);
}

}  // namespace stickslip::testing
