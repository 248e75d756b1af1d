// DenseLu (LAPACK) against its contract: solves to backward-stable accuracy, the rcond estimate
// brackets the exact 1 / (‖A‖₁ ‖A⁻¹‖₁), singular and non-finite matrices are refused.
#include "linalg/dense_lu.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

namespace stickslip {
namespace {

Eigen::MatrixXd random_matrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) A(i, j) = dist(rng);
  }
  return A;
}

TEST(DenseLu, SolvesToBackwardStableAccuracy) {
  // Partial pivoting: ‖A x − b‖ ≲ n eps ‖A‖ ‖x‖ for random matrices (growth factor O(1)).
  constexpr double kBackwardError = 1e-12;
  for (int n : {1, 7, 180}) {
    const Eigen::MatrixXd A = random_matrix(n, 3 + n);
    const Eigen::VectorXd b = random_matrix(n, 5).col(0);
    DenseLu lu;
    ASSERT_TRUE(lu.compute(A));
    const Eigen::VectorXd x = lu.solve(b);
    EXPECT_LE((A * x - b).norm(), kBackwardError * A.norm() * x.norm()) << n;
  }
}

TEST(DenseLu, RcondEstimatesTheExactReciprocalCondition) {
  // LAPACK's estimate of ‖A⁻¹‖₁ is a lower bound, in practice within a factor 3 of it.
  constexpr double kEstimateFactor = 3.0;
  // The reference inverse itself is accurate to ~cond·eps (≤ 1e-6 here).
  for (double scale : {1.0, 1e-4, 1e-8}) {
    Eigen::MatrixXd A = random_matrix(40, 11);
    const Eigen::VectorXd r = random_matrix(40, 13).col(0);
    A.col(3) = A.col(4) + scale * r;  // nearly dependent columns: condition ~ 1/scale
    const double exact = 1.0 / (A.cwiseAbs().colwise().sum().maxCoeff() *
                                A.inverse().cwiseAbs().colwise().sum().maxCoeff());
    DenseLu lu;
    ASSERT_TRUE(lu.compute(A));
    EXPECT_GE(lu.rcond(), exact * (1 - 1e-6)) << scale;
    EXPECT_LE(lu.rcond(), kEstimateFactor * exact) << scale;
  }
}

TEST(DenseLu, RefusesSingularAndNonFiniteMatrices) {
  Eigen::MatrixXd A = random_matrix(5, 2);
  A.row(2).setZero();
  DenseLu lu;
  EXPECT_FALSE(lu.compute(A));
  EXPECT_EQ(lu.rcond(), 0.0);
  Eigen::MatrixXd B = random_matrix(5, 2);
  B(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(lu.compute(B));
  EXPECT_FALSE(lu.compute(Eigen::MatrixXd(0, 0)));
}

}  // namespace
}  // namespace stickslip
