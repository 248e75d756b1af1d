// Shared checks of the harmonic-balance tests.
#pragma once

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "hbm/harmonic_balance.h"

namespace stickslip::testing {

// The analytic dR/dx and dR/dΩ of `sys` at (x, omega) against central differences with steps
// x_step (every unknown) and 1e-6 omega; both must agree to `tolerance` relative (Frobenius and
// 2-norm of the derivative).
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
}

}  // namespace stickslip::testing
