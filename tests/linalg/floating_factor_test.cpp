// FloatingFactor against dense references: free spring–mass chains (one rigid mode per connected
// piece), the pseudo-inverse solve K⁺b checked by its defining equations, the kept elastic modes
// against Eigen's dense generalised eigen-solver.
#include "linalg/floating_factor.h"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "core/errors.h"

namespace stickslip {
namespace {

// Chains of masses m_i = 1 + 0.1 i joined by springs k_i = 1000 (1 + 0.05 i); a chain is cut
// (no spring) before each index in `cuts`, making one more free piece.
void chain(int n, const std::vector<int>& cuts, SparseMatrix& K, SparseMatrix& M) {
  std::vector<Eigen::Triplet<double>> kt, mt;
  for (int i = 0; i < n; ++i) mt.emplace_back(i, i, 1.0 + 0.1 * i);
  for (int i = 0; i + 1 < n; ++i) {
    if (std::find(cuts.begin(), cuts.end(), i + 1) != cuts.end()) continue;
    const double k = 1000.0 * (1.0 + 0.05 * i);
    kt.emplace_back(i, i, k);
    kt.emplace_back(i + 1, i + 1, k);
    kt.emplace_back(i, i + 1, -k);
    kt.emplace_back(i + 1, i, -k);
  }
  K.resize(n, n);
  M.resize(n, n);
  K.setFromTriplets(kt.begin(), kt.end());
  M.setFromTriplets(mt.begin(), mt.end());
}

TEST(FloatingFactor, FreeChainsHaveOneRigidModePerPieceAndSolveThePseudoInverse) {
  for (const std::vector<int>& cuts : {std::vector<int>{}, std::vector<int>{40}}) {
    const int n = 100;
    SparseMatrix K, M;
    chain(n, cuts, K, M);
    const Eigen::MatrixXd Kd(K), Md(M);
    SparseCholesky plain(K);
    EXPECT_FALSE(plain.ok() && factor_gives_back(plain, K));  // singular: not to be trusted
    FloatingFactor factor;
    ASSERT_TRUE(factor.compute(K, M, {.num_elastic_modes = 3, .modal = {}})) << factor.message();
    const int pieces = 1 + static_cast<int>(cuts.size());
    ASSERT_EQ(factor.num_rigid(), pieces);
    const Eigen::MatrixXd rigid = factor.rigid_modes();
    EXPECT_LT((Kd * rigid).norm(), 1e-9 * Kd.norm());
    EXPECT_LT((rigid.transpose() * Md * rigid - Eigen::MatrixXd::Identity(pieces, pieces)).norm(),
              1e-10);
    // Kept elastic eigenvalues against the dense solve (its first `pieces` are the zero ones).
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(Kd, Md);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(factor.eigenvalues()(pieces + j), dense.eigenvalues()(pieces + j),
                  1e-8 * dense.eigenvalues()(pieces + j));
    }
    // X = K⁺B: K X = B − MΦ_0Φ_0ᵀB and Φ_0ᵀ M X = 0, for a B with components on the rigid modes.
    Eigen::MatrixXd B(n, 2);
    for (int i = 0; i < n; ++i) {
      B(i, 0) = std::sin(0.3 * i) + 0.2;
      B(i, 1) = (i % 7) - 3.0;
    }
    FloatingSolveSummary summary;
    const Eigen::MatrixXd X = factor.solve(B, &summary);
    EXPECT_TRUE(summary.converged);
    EXPECT_LE(summary.steps, 5);
    const Eigen::MatrixXd B_d = B - Md * rigid * (rigid.transpose() * B);
    EXPECT_LT((Kd * X - B_d).norm(), 1e-10 * B.norm());
    EXPECT_LT((rigid.transpose() * Md * X).norm(), 1e-12 * rigid.norm() * (Md * X).norm());
    EXPECT_THROW(factor.solve(Eigen::MatrixXd::Zero(n + 1, 1)), InvalidInput);
  }
}

TEST(FloatingFactor, IndefiniteStiffnessIsReportedNotThrown) {
  SparseMatrix K, M;
  chain(10, {}, K, M);
  const SparseMatrix minus_K = -K;
  FloatingFactor factor;
  EXPECT_FALSE(factor.compute(minus_K, M, {}));
  EXPECT_TRUE(factor.factor_failed());
  EXPECT_FALSE(factor.message().empty());
  EXPECT_THROW(factor.solve(Eigen::MatrixXd::Zero(10, 1)), InvalidInput);
}

}  // namespace
}  // namespace stickslip
