#include "continuation/gmres.h"

#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "continuation/newton.h"
#include "continuation/parametrized_system.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// GMRES's own stopping test is 1e-12 relative; the dense LU of these well-conditioned matrices
// (cond < 1e3) is accurate to ~1e-13, so the two solutions must agree to ~1e-9.
constexpr double kSolveTolerance = 1e-12;
constexpr double kAgreement = 1e-9;

MatrixXd random_matrix(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatrixXd A(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) A(i, j) = u(gen);
  return A;
}

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

// R(x) = A x + 0.1 x³ (componentwise) − b: solved by Newton with the dense Jacobian and with a
// structured solve (GMRES on the same Jacobian). The iterates must agree (the structured step is
// exact to 1e-12 relative).
class CubicSystem : public ParametrizedSystem {
 public:
  CubicSystem(MatrixXd A, VectorXd b, bool structured)
      : A_(std::move(A)), b_(std::move(b)), structured_(structured) {}
  int size() const override { return static_cast<int>(b_.size()); }
  void evaluate(const VectorXd& x, double, VectorXd& R, MatrixXd* J, VectorXd* Rl) const override {
    R = A_ * x + 0.1 * x.array().cube().matrix() - b_;
    if (J) *J = jacobian(x);
    if (Rl) Rl->setZero(size());
  }
  bool has_structured_jacobian() const override { return structured_; }
  bool solve_jacobian(const VectorXd& x, double, const VectorXd& rhs, VectorXd& dx) const override {
    const MatrixXd J = jacobian(x);
    GmresOptions o;
    o.tolerance = kSolveTolerance;
    ++solves;
    return gmres([&](const VectorXd& v) -> VectorXd { return J * v; },
                 [](const VectorXd& v) -> VectorXd { return v; }, rhs, dx, o)
        .converged;
  }
  mutable int solves = 0;

 private:
  MatrixXd jacobian(const VectorXd& x) const {
    MatrixXd J = A_;
    J.diagonal() += 0.3 * x.array().square().matrix();
    return J;
  }
  MatrixXd A_;
  VectorXd b_;
  bool structured_;
};

TEST(Gmres, StructuredNewtonMatchesDenseNewton) {
  const int n = 30;
  const MatrixXd A = 4.0 * MatrixXd::Identity(n, n) + random_matrix(n, 11) / std::sqrt(n);
  const VectorXd b = 3.0 * random_matrix(n, 12).col(0);
  const CubicSystem dense(A, b, false), structured(A, b, true);
  NewtonOptions o;
  o.tolerance = 1e-13;
  o.reuse_jacobian = false;  // the structured solve takes no chord steps: compare Newton steps
  VectorXd xd = VectorXd::Zero(n), xs = VectorXd::Zero(n);
  const NewtonSummary sd = solve_newton(dense, 0.0, xd, o);
  const NewtonSummary ss = solve_newton(structured, 0.0, xs, o);
  ASSERT_TRUE(sd.converged());
  ASSERT_TRUE(ss.converged());
  EXPECT_GT(structured.solves, 0);
  EXPECT_EQ(dense.solves, 0);
  ASSERT_EQ(sd.residual_history.size(), ss.residual_history.size());
  for (size_t i = 0; i + 1 < sd.residual_history.size(); ++i) {  // the same iterates
    EXPECT_NEAR(ss.residual_history[i], sd.residual_history[i],
                kAgreement * sd.residual_history[0]);
  }
  EXPECT_LE((xs - xd).norm(), kAgreement * xd.norm());
}

}  // namespace
}  // namespace stickslip
