// Newton with a structured Jacobian solve (ParametrizedSystem::solve_jacobian through GMRES,
// linalg/gmres.h) against Newton with the dense Jacobian: the same iterates.
#include <cmath>
#include <random>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "../linalg/random_dense.h"
#include "continuation/newton.h"
#include "continuation/parametrized_system.h"
#include "linalg/gmres.h"
#include "test_systems.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

using dense_test::kAgreement;
using dense_test::kSolveTolerance;
using dense_test::random_matrix;

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

TEST(Gmres, CubicSystemJacobianPassesTheDerivativeChecks) {
  const int n = 30;
  const MatrixXd A = 4.0 * MatrixXd::Identity(n, n) + random_matrix(n, 11) / std::sqrt(n);
  const CubicSystem system(A, 3.0 * random_matrix(n, 12).col(0), false);
  testing::expect_jacobians_match_finite_differences(system, random_matrix(n, 13).col(0), 0.0);
}

}  // namespace
}  // namespace stickslip
