// Helpers shared by the continuation tests: a ParametrizedSystem from a lambda, a finite-difference
// check of its hand-written Jacobians, and a check that a callable throws InvalidInput naming a
// field.
#pragma once

#include <algorithm>
#include <functional>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "../derivative_check.h"
#include "continuation/parametrized_system.h"
#include "core/errors.h"

namespace stickslip::testing {

// R(x, λ) given by a function that fills R and, when non-null, dR/dx and dR/dλ.
class FunctionSystem final : public ParametrizedSystem {
 public:
  using Function = std::function<void(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& R,
                                      Eigen::MatrixXd* dR_dx, Eigen::VectorXd* dR_dlambda)>;
  FunctionSystem(int n, Function f, double residual_scale = 1.0)
      : n_(n), f_(std::move(f)), scale_(residual_scale) {}
  int size() const override { return n_; }
  double residual_scale() const override { return scale_; }
  void evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& R, Eigen::MatrixXd* dR_dx,
                Eigen::VectorXd* dR_dlambda) const override {
    ++evaluations;
    R.resize(n_);
    if (dR_dx) dR_dx->resize(n_, n_);
    if (dR_dlambda) dR_dlambda->resize(n_);
    f_(x, lambda, R, dR_dx, dR_dlambda);
  }
  mutable int evaluations = 0;

 private:
  int n_;
  Function f_;
  double scale_;
};

// Central differences: error O(h²)·|R'''| + O(eps/h)·|R|; with h = 1e-6 relative to the
// variables' size (O(1) in these tests) both terms are below 1e-8.
constexpr double kFdStep = 1e-6;
constexpr double kFdTolerance = 1e-7;

// Compares dR/dx and dR/dλ of sys at (x, λ) with central differences (relative to the largest
// entry, at least 1).
inline void expect_jacobians_match_finite_differences(const ParametrizedSystem& sys,
                                                      const Eigen::VectorXd& x, double lambda) {
  const int n = sys.size();
  Eigen::VectorXd R, Rp, Rm, dR_dlambda;
  Eigen::MatrixXd J;
  sys.evaluate(x, lambda, R, &J, &dR_dlambda);
  Eigen::MatrixXd J_fd(n, n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp(j) += kFdStep;
    xm(j) -= kFdStep;
    sys.evaluate(xp, lambda, Rp, nullptr, nullptr);
    sys.evaluate(xm, lambda, Rm, nullptr, nullptr);
    J_fd.col(j) = (Rp - Rm) / (2 * kFdStep);
  }
  sys.evaluate(x, lambda + kFdStep, Rp, nullptr, nullptr);
  sys.evaluate(x, lambda - kFdStep, Rm, nullptr, nullptr);
  const Eigen::VectorXd dR_dlambda_fd = (Rp - Rm) / (2 * kFdStep);
  const double ref = std::max(1.0, J.cwiseAbs().maxCoeff());
  EXPECT_LE((J - J_fd).cwiseAbs().maxCoeff(), kFdTolerance * ref) << "dR/dx\n"
                                                                  << J << "\nfd\n"
                                                                  << J_fd;
  const double ref_l = std::max(1.0, dR_dlambda.cwiseAbs().maxCoeff());
  EXPECT_LE((dR_dlambda - dR_dlambda_fd).cwiseAbs().maxCoeff(), kFdTolerance * ref_l)
      << "dR/dlambda " << dR_dlambda.transpose() << " fd " << dR_dlambda_fd.transpose();
  // The Taylor slope along a fixed mixed direction (derivative_check.h).
  Eigen::VectorXd dx(n);
  for (int j = 0; j < n; ++j) dx[j] = std::cos(1.0 + 2.7 * j);
  expect_taylor_slope(taylor_remainder(sys, x, lambda, dx, 0.5));
}

// Expects f() to throw InvalidInput whose message names `field`.
template <class F>
void expect_invalid_input_naming(F&& f, const std::string& field) {
  try {
    f();
    ADD_FAILURE() << "no InvalidInput thrown; expected one naming " << field;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos)
        << "message '" << e.what() << "' does not name " << field;
  }
}

}  // namespace stickslip::testing
