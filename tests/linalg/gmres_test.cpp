#include "linalg/gmres.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "random_dense.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

using dense_test::kAgreement;
using dense_test::kSolveTolerance;
using dense_test::random_matrix;

TEST(Gmres, MatchesDenseLuWithRestartsAndPreconditioner) {
  const int n = 60;
  // Nonsymmetric, eigenvalues spread around 3 ± 1: converges, but needs several restarts of 5.
  const MatrixXd A = 3.0 * MatrixXd::Identity(n, n) + random_matrix(n, 7) / std::sqrt(n);
  const VectorXd b = random_matrix(n, 8).col(0);
  const VectorXd exact = A.partialPivLu().solve(b);
  GmresOptions o;
  o.tolerance = kSolveTolerance;
  o.restart = 5;
  auto apply = [&](const VectorXd& v) -> VectorXd { return A * v; };
  auto none = [](const VectorXd& v) -> VectorXd { return v; };
  VectorXd x;
  const GmresSummary s = gmres(apply, none, b, x, o);
  EXPECT_TRUE(s.converged);
  EXPECT_GT(s.iterations, o.restart);  // the restarts were exercised
  EXPECT_LE((x - exact).norm(), kAgreement * exact.norm());
  EXPECT_LE((b - A * x).norm(), kSolveTolerance * b.norm() * 1.0001);

  // With the exact inverse as the preconditioner GMRES converges in one product.
  const Eigen::PartialPivLU<MatrixXd> lu(A);
  auto exact_pre = [&](const VectorXd& v) -> VectorXd { return lu.solve(v); };
  const GmresSummary s1 = gmres(apply, exact_pre, b, x, o);
  EXPECT_TRUE(s1.converged);
  EXPECT_EQ(s1.iterations, 1);
  EXPECT_LE((x - exact).norm(), kAgreement * exact.norm());
}

TEST(Gmres, ReportsNonConvergence) {
  const int n = 40;
  const MatrixXd A = MatrixXd::Identity(n, n) + 5.0 * random_matrix(n, 3);
  const VectorXd b = VectorXd::Ones(n);
  GmresOptions o;
  o.restart = 2;
  o.max_iterations = 4;
  VectorXd x;
  const GmresSummary s = gmres([&](const VectorXd& v) -> VectorXd { return A * v; },
                               [](const VectorXd& v) -> VectorXd { return v; }, b, x, o);
  EXPECT_FALSE(s.converged);
  EXPECT_GT(s.relative_residual, o.tolerance);
}

}  // namespace
}  // namespace stickslip
