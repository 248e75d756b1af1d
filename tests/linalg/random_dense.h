// Shared by the GMRES tests (tests/linalg/gmres_test.cpp) and the structured-Newton tests
// (tests/continuation/structured_newton_test.cpp): seeded random dense matrices and the
// tolerances of a GMRES solve compared with a dense LU.
#pragma once

#include <random>

#include <Eigen/Dense>

namespace stickslip::dense_test {

// GMRES's own stopping test is 1e-12 relative; the dense LU of these well-conditioned matrices
// (cond < 1e3) is accurate to ~1e-13, so the two solutions must agree to ~1e-9.
constexpr double kSolveTolerance = 1e-12;
constexpr double kAgreement = 1e-9;

// n x n entries uniform in [-1, 1], the same for the same seed.
inline Eigen::MatrixXd random_matrix(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) A(i, j) = u(gen);
  return A;
}

}  // namespace stickslip::dense_test
