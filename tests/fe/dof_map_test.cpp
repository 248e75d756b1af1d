// DofMap with linear multi-point constraints (*EQUATION): the transformation, its resolution of
// chains and clamped terms, and the rules it refuses, against dense matrices built in the test.
#include "fe/dof_map.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/errors.h"

namespace stickslip {
namespace {

// Round-off of a few dense products of O(1) numbers.
constexpr double kTolerance = 1e-13;

SparseMatrix random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = u(rng);
  const Eigen::MatrixXd S = A * A.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  return S.sparseView();
}

LinearConstraint eq(std::vector<int> dofs, std::vector<double> c, const char* origin) {
  return {std::move(dofs), std::move(c), origin};
}

TEST(DofMapEquations, RestrictIsTransposedTransformTimesMatrixTimesTransform) {
  // 12 DOFs (4 nodes). Clamped: 0, 1, 2. Equations (first DOF dependent):
  //   2 u3 - u6 - u9 = 0        -> u3 = 0.5 u6 + 0.5 u9
  //   u4 - u3 + 3 u0 = 0        -> u4 = u3 (chain; u0 clamped drops out) = 0.5 u6 + 0.5 u9
  //   u5 + 2 u7 = 0             -> u5 = -2 u7
  const std::vector<LinearConstraint> eqs = {eq({3, 6, 9}, {2, -1, -1}, "a:1"),
                                             eq({4, 3, 0}, {1, -1, 3}, "a:2"),
                                             eq({5, 7}, {1, 2}, "a:3")};
  const std::vector<int> clamped = {0, 1, 2};
  const DofMap map(12, clamped, eqs);
  EXPECT_EQ(map.num_free(), 6);  // 6, 7, 8, 9, 10, 11
  EXPECT_TRUE(map.is_dependent(3) && map.is_dependent(4) && map.is_dependent(5));
  EXPECT_TRUE(map.is_clamped(0) && !map.is_dependent(0));
  EXPECT_EQ(map.dependent_origin(4), "a:2");
  // T written by hand.
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(12, 6);
  for (int f = 0; f < 6; ++f) T(6 + f, f) = 1.0;
  T(3, 0) = T(3, 3) = 0.5;
  T(4, 0) = T(4, 3) = 0.5;
  T(5, 1) = -2.0;
  EXPECT_LT((Eigen::MatrixXd(map.transformation()) - T).norm(), kTolerance);
  const SparseMatrix K = random_spd(12, 7);
  const Eigen::MatrixXd Kr = T.transpose() * Eigen::MatrixXd(K) * T;
  EXPECT_LT((Eigen::MatrixXd(map.restrict(K)) - Kr).norm(), kTolerance * Kr.norm());
  // condense: the same numbers in the full numbering, nothing on non-free rows and columns.
  const Eigen::MatrixXd C(map.condense(K));
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) EXPECT_NEAR(C(6 + a, 6 + b), Kr(a, b), kTolerance * Kr.norm());
  EXPECT_EQ(C.topRows(6).norm(), 0.0);
  EXPECT_EQ(C.leftCols(6).norm(), 0.0);
  // expand = T x_f, restrict_load = T^T f, restrict(x) = x_f; work is invariant.
  const Eigen::VectorXd xf = Eigen::VectorXd::LinSpaced(6, 1.0, 2.0);
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(12, -1.0, 3.0);
  EXPECT_LT((map.expand(xf) - T * xf).norm(), kTolerance);
  EXPECT_LT((map.restrict_load(f) - T.transpose() * f).norm(), kTolerance);
  EXPECT_LT((map.restrict(Eigen::VectorXd(T * xf)) - xf).norm(), kTolerance);
  const Eigen::MatrixXcd F = f.cast<std::complex<double>>() * std::complex<double>(1, 2);
  EXPECT_LT((map.restrict_load(F).col(0) -
             (T.transpose() * f).cast<std::complex<double>>() * std::complex<double>(1, 2))
                .norm(),
            kTolerance);
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(12, 2);
  X.bottomRows(6) << xf, 2 * xf;
  map.fill_dependent_rows(X);
  EXPECT_LT((X.col(1) - 2 * T * xf).norm(), kTolerance);
  EXPECT_LT((map.expand(Eigen::MatrixXd(X.bottomRows(6))) - X).norm(), kTolerance);
}

TEST(DofMapEquations, WithoutEquationsRestrictIsTheFreeBlock) {
  const SparseMatrix K = random_spd(6, 3);
  const std::vector<int> clamped = {1, 4};
  const DofMap map(6, clamped);
  EXPECT_FALSE(map.has_dependents());
  const Eigen::MatrixXd T(map.transformation());
  EXPECT_EQ((Eigen::MatrixXd(map.restrict(K)) - T.transpose() * Eigen::MatrixXd(K) * T).norm(),
            0.0);
}

TEST(DofMapEquations, AClampedDependentIsAcceptedOnlyWhenItsEquationReadsZeroEqualsZero) {
  const std::vector<int> clamped = {0, 1, 2};
  // u0 = u1 with both clamped: 0 = 0, fine; u0 stays clamped.
  const std::vector<LinearConstraint> ok = {eq({0, 1}, {1, -1}, "d:1")};
  const DofMap map(6, clamped, ok);
  EXPECT_TRUE(map.is_clamped(0));
  EXPECT_EQ(map.num_free(), 3);
  // u0 = u3 with u3 free: refused, naming the equation.
  const std::vector<LinearConstraint> bad = {eq({0, 3}, {1, -1}, "d:7")};
  try {
    DofMap(6, clamped, bad);
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(e.message().find("is clamped and is the dependent"), std::string::npos)
        << e.message();
    EXPECT_NE(e.message().find("d:7"), std::string::npos);
  }
}

TEST(DofMapEquations, CyclesAndTwoEquationsForOneDofAreRefused) {
  const std::vector<LinearConstraint> cycle = {eq({0, 1}, {1, -1}, "c:1"),
                                               eq({1, 2}, {1, -1}, "c:2"),
                                               eq({2, 0}, {1, -1}, "c:3")};
  try {
    DofMap(6, {}, cycle);
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(e.message().find("cycle"), std::string::npos) << e.message();
  }
  const std::vector<LinearConstraint> twice = {eq({0, 1}, {1, -1}, "t:1"),
                                               eq({0, 2}, {1, -1}, "t:2")};
  try {
    DofMap(6, {}, twice);
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(e.message().find("two equations, at t:1 and t:2"), std::string::npos)
        << e.message();
  }
}

// Supports (support_constraints, DofMap::from_supports): the space of admissible displacements
// T must be exactly {u : d·u_node = 0 for every support direction d of the node}, checked with
// the orthogonal projector built in the test from the directions.
Eigen::MatrixXd dense_transformation(const DofMap& map) { return Eigen::MatrixXd(map.transformation()); }

TEST(DofMapSupports, LocalDirectionsLeaveExactlyTheOrthogonalComplementFree) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.8, 0.52).normalized();
  const Eigen::Vector3d a = Eigen::Vector3d(0.9, 0.1, -0.4).normalized();
  // Node 0: one direction (a roller on an inclined plane); node 1: two (a line); node 2: the
  // same direction twice and a combination of them (rank 1); node 3: three (held).
  const std::vector<NodeSupport> supports = {
      {0, {n}, "c:1"}, {1, {n, a}, "c:2"}, {2, {n, -2.0 * n}, "c:3"}, {2, {n}, "c:4"},
      {3, {n, a, n.cross(a)}, "c:5"}};
  const DofMap map = DofMap::from_supports(5, {}, supports);
  const std::vector<std::vector<Eigen::Vector3d>> held = {{n}, {n, a}, {n}, {n, a, n.cross(a)}, {}};
  const std::vector<int> free_per_node = {2, 1, 2, 0, 3};
  EXPECT_EQ(map.num_free(), 8);
  const Eigen::MatrixXd T = dense_transformation(map);
  for (int node = 0; node < 5; ++node) {
    const Eigen::MatrixXd Tn = T.middleRows(3 * node, 3);
    // Every admissible displacement is orthogonal to the held directions ...
    for (const Eigen::Vector3d& d : held[node]) {
      EXPECT_LT((d.transpose() * Tn).cwiseAbs().maxCoeff(), kTolerance) << "node " << node;
    }
    // ... and they span the whole complement (rank = 3 - rank of the held directions).
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Tn);
    EXPECT_EQ(lu.rank(), free_per_node[node]) << "node " << node;
  }
}

TEST(DofMapSupports, AxisDirectionsClampTheirDofAndCombineWithClampsAndEquations) {
  // Node 0 supported in y (a symmetry plane), node 1 in x and -z, node 2 clamped and supported
  // along a skew direction (the support adds nothing), node 3 tied by an equation u_3x = u_1y.
  const Eigen::Vector3d skew = Eigen::Vector3d(1, 1, 0).normalized();
  const std::vector<NodeSupport> supports = {
      {0, {Eigen::Vector3d::UnitY()}, "s:1"}, {1, {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ()}, "s:2"},
      {2, {skew}, "s:3"}};
  const SupportConstraints sc = support_constraints(4, supports);
  EXPECT_EQ(sc.clamped, (std::vector<int>{1, 3, 5}));
  ASSERT_EQ(sc.equations.size(), 1u);
  const std::vector<int> clamp = {2};
  const std::vector<LinearConstraint> eqs = {eq({9, 4}, {1, -1}, "m:1")};
  const DofMap map = DofMap::from_supports(4, clamp, supports, eqs);
  for (int dof : {1, 3, 5, 6, 7, 8}) EXPECT_TRUE(map.is_clamped(dof)) << dof;
  EXPECT_TRUE(map.is_dependent(9));
  EXPECT_EQ(map.num_free(), 12 - 6 - 1);
}

TEST(DofMapSupports, BadSupportsAreRefusedNamingTheirOrigin) {
  const std::vector<NodeSupport> zero = {{0, {Eigen::Vector3d::Zero()}, "case.yaml:7"}};
  const std::vector<NodeSupport> outside = {{4, {Eigen::Vector3d::UnitX()}, "case.yaml:8"}};
  for (const auto* s : {&zero, &outside}) {
    try {
      support_constraints(2, *s);
      ADD_FAILURE() << "accepted";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find((*s)[0].origin), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace stickslip
