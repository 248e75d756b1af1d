#include "linalg/sparse_cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cstdio>
#include <random>
#include <vector>

#include "core/errors.h"
#include "linalg/blas_threads.h"

namespace stickslip {
namespace {

// A dense-checkable SPD matrix: 1D Laplacian plus a random sparse SPD perturbation, seeded.
SparseMatrix random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> index(0, n - 1);
  std::vector<Triplet> triplets;
  for (int i = 0; i < n; ++i) {
    triplets.emplace_back(i, i, 4.0);
    if (i + 1 < n) {
      triplets.emplace_back(i, i + 1, -1.0);
      triplets.emplace_back(i + 1, i, -1.0);
    }
  }
  // B Bᵀ with sparse B keeps A symmetric positive definite.
  std::vector<Triplet> b;
  for (int k = 0; k < 3 * n; ++k) b.emplace_back(index(rng), index(rng), value(rng));
  SparseMatrix B(n, n);
  B.setFromTriplets(b.begin(), b.end());
  SparseMatrix A(n, n);
  A.setFromTriplets(triplets.begin(), triplets.end());
  return SparseMatrix(A + SparseMatrix(B * SparseMatrix(B.transpose())));
}

// Solution accuracy of a backward-stable Cholesky on a matrix with condition number ~1e2.
constexpr double kSolveTolerance = 1e-12;

TEST(SparseCholesky, SolvesManyRightHandSides) {
  const int n = 60;
  const SparseMatrix A = random_spd(n, 1);
  SparseCholesky cholesky(A);
  ASSERT_TRUE(cholesky.ok()) << cholesky.message();
  EXPECT_EQ(cholesky.size(), n);
  EXPECT_GT(cholesky.factor_nonzeros(), 0.0);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd B(n, 5);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = value(rng);
  const Eigen::MatrixXd X = cholesky.solve(B);
  const Eigen::MatrixXd reference = Eigen::MatrixXd(A).llt().solve(B);
  EXPECT_LT((X - reference).norm() / reference.norm(), kSolveTolerance);
  EXPECT_LT((A * X - B).norm() / B.norm(), kSolveTolerance);

  Eigen::VectorXd y(n);
  cholesky.solve(B.col(3).data(), y.data());
  EXPECT_LT((y - reference.col(3)).norm() / reference.col(3).norm(), kSolveTolerance);
}

TEST(SparseCholesky, HalfSolvesComposeToTheInverseAndWhitenA) {
  const int n = 50;
  const SparseMatrix A = random_spd(n, 8);
  const SparseCholesky cholesky(A);
  ASSERT_TRUE(cholesky.ok()) << cholesky.message();
  const Eigen::MatrixXd Ad = Eigen::MatrixXd(A);
  Eigen::MatrixXd Ginv(n, n), GinvT(n, n);  // G⁻¹ and G⁻ᵀ column by column
  for (int j = 0; j < n; ++j) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(n, j);
    cholesky.solve_lower(e.data(), Ginv.col(j).data());
    cholesky.solve_upper(e.data(), GinvT.col(j).data());
  }
  EXPECT_LT((GinvT - Ginv.transpose()).norm(), kSolveTolerance * Ginv.norm());
  EXPECT_LT((GinvT * Ginv - Ad.inverse()).norm(), kSolveTolerance * Ad.inverse().norm());
  EXPECT_LT((Ginv * Ad * GinvT - Eigen::MatrixXd::Identity(n, n)).norm(), kSolveTolerance * n);

  // Block half solves: all columns at once give the same as column by column.
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  EXPECT_LT((cholesky.solve_lower(I) - Ginv).norm(), kSolveTolerance * Ginv.norm());
  EXPECT_LT((cholesky.solve_upper(I) - GinvT).norm(), kSolveTolerance * GinvT.norm());
}

TEST(SparseCholesky, EstimateMatchesTheActualFactor) {
  const SparseMatrix A = random_spd(80, 9);
  const CholeskyEstimate estimate = SparseCholesky::estimate(A);
  const SparseCholesky cholesky(A);
  ASSERT_TRUE(cholesky.ok());
  EXPECT_EQ(estimate.factor_nonzeros, cholesky.factor_nonzeros());
  EXPECT_EQ(estimate.ordering, cholesky.ordering());
  // A dense n x n Cholesky needs n³/3 flops; the sparse one fewer, but more than nnz(L).
  EXPECT_GT(estimate.flops, estimate.factor_nonzeros);
  EXPECT_LE(estimate.flops, 80.0 * 80.0 * 80.0);
}

TEST(SparseCholesky, ReadsOnlyTheLowerTriangle) {
  const int n = 30;
  const SparseMatrix A = random_spd(n, 4);
  // Garbage in the strict upper triangle must not change the factor.
  SparseMatrix lower_plus_garbage = A;
  for (int k = 0; k < lower_plus_garbage.outerSize(); ++k) {
    for (SparseMatrix::InnerIterator it(lower_plus_garbage, k); it; ++it) {
      if (it.row() < it.col()) it.valueRef() = 1e6;
    }
  }
  SparseCholesky cholesky(lower_plus_garbage);
  ASSERT_TRUE(cholesky.ok()) << cholesky.message();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  const Eigen::VectorXd x = cholesky.solve(Eigen::MatrixXd(b));
  EXPECT_LT((A * x - b).norm() / b.norm(), kSolveTolerance);
}

TEST(SparseCholesky, IndefiniteMatrixIsReportedNotThrown) {
  const int n = 20;
  SparseMatrix A = random_spd(n, 5);
  A.coeffRef(7, 7) = -50.0;  // a negative diagonal entry: not positive definite
  SparseCholesky cholesky(A);
  EXPECT_FALSE(cholesky.ok());
  EXPECT_NE(cholesky.message().find("not positive definite"), std::string::npos)
      << cholesky.message();
  EXPECT_THROW(cholesky.solve(Eigen::MatrixXd::Ones(n, 1)), InvalidInput);
}

TEST(SparseCholesky, SizeMismatchThrows) {
  SparseCholesky cholesky(random_spd(10, 6));
  ASSERT_TRUE(cholesky.ok());
  EXPECT_THROW(cholesky.solve(Eigen::MatrixXd::Ones(9, 1)), InvalidInput);
  EXPECT_THROW(SparseCholesky(SparseMatrix(3, 4)), InvalidInput);
}

// 7-point Laplacian of a g x g x g grid plus the identity (SPD, sparse: many supernodes).
SparseMatrix grid_laplacian(int g) {
  auto id = [g](int i, int j, int k) { return i + g * (j + g * k); };
  std::vector<Triplet> t;
  for (int k = 0; k < g; ++k)
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i) {
        const int a = id(i, j, k);
        t.emplace_back(a, a, 7.0);
        const int neighbours[3] = {i + 1 < g ? id(i + 1, j, k) : -1,
                                   j + 1 < g ? id(i, j + 1, k) : -1,
                                   k + 1 < g ? id(i, j, k + 1) : -1};
        for (int b : neighbours) {
          if (b < 0) continue;
          t.emplace_back(a, b, -1.0);
          t.emplace_back(b, a, -1.0);
        }
      }
  SparseMatrix A(g * g * g, g * g * g);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(SparseCholesky, TrailingOrderingSkipsTheForwardSolveExactly) {
  const int g = 9, n = g * g * g;
  const SparseMatrix A = grid_laplacian(g);
  // `last`: the nodes of the face k = g − 1, in a scrambled order.
  std::vector<int> last;
  for (int a = 0; a < g * g; ++a) last.push_back(n - g * g + (a * 7) % (g * g));
  const int m = static_cast<int>(last.size());
  SparseCholesky cholesky;
  ASSERT_TRUE(cholesky.factorize(A, last, LastOrdering::kAlways)) << cholesky.message();
  ASSERT_EQ(cholesky.num_last(), m);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd B_last(m, 4);
  for (Eigen::Index i = 0; i < B_last.size(); ++i) B_last.data()[i] = value(rng);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, 4);
  for (int j = 0; j < m; ++j) B.row(last[j]) = B_last.row(j);

  // G⁻¹ b: zero above the trailing block (exactly: the forward solve of zeros), and the
  // trailing rows from the dense triangular solve.
  const Eigen::MatrixXd Y = cholesky.solve_lower(B);
  EXPECT_EQ(Y.topRows(n - m).cwiseAbs().maxCoeff(), 0.0);
  const Eigen::MatrixXd Z = cholesky.solve_lower_last(B_last);
  EXPECT_LT((Z - Y.bottomRows(m)).norm(), kSolveTolerance * Z.norm());
  // G⁻ᵀ [0; Z] = A⁻¹ b, against a dense Cholesky.
  Eigen::MatrixXd padded = Eigen::MatrixXd::Zero(n, 4);
  padded.bottomRows(m) = Z;
  const Eigen::MatrixXd X = cholesky.solve_upper(padded);
  const Eigen::MatrixXd reference = Eigen::MatrixXd(A).llt().solve(B);
  EXPECT_LT((X - reference).norm(), kSolveTolerance * reference.norm());
  // bᵀ A⁻¹ b = Zᵀ Z (the Craig–Bampton Schur-complement identity).
  EXPECT_LT((Z.transpose() * Z - B.transpose() * reference).norm(),
            kSolveTolerance * (Z.transpose() * Z).norm());
}

TEST(SparseCholesky, TrailingOrderingCanBeRefusedAndChecksItsIndices) {
  const SparseMatrix A = grid_laplacian(5);
  const std::vector<int> last = {3, 17, 60};
  SparseCholesky never;
  ASSERT_TRUE(never.factorize(A, last, LastOrdering::kNever));
  EXPECT_EQ(never.num_last(), 0);
  EXPECT_THROW(never.solve_lower_last(Eigen::MatrixXd::Ones(3, 1)), InvalidInput);
  SparseCholesky automatic;
  ASSERT_TRUE(automatic.factorize(A, last, LastOrdering::kAuto, 100.0, 0.0));
  EXPECT_TRUE(automatic.num_last() == 0 || automatic.num_last() == 3);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), 1.0, 2.0);
  EXPECT_LT((A * automatic.solve(Eigen::MatrixXd(b)) - b).norm() / b.norm(), kSolveTolerance);
  SparseCholesky bad;
  const std::vector<int> repeated = {3, 3}, outside = {125};
  EXPECT_THROW(bad.factorize(A, repeated, LastOrdering::kAlways), InvalidInput);
  EXPECT_THROW(bad.factorize(A, outside, LastOrdering::kAlways), InvalidInput);
}

TEST(ScopedBlasThreads, NestsAndRestores) {
  // A no-op without OpenBLAS; with it, solves still work inside the scope.
  const SparseMatrix A = random_spd(40, 12);
  const SparseCholesky cholesky(A);
  ASSERT_TRUE(cholesky.ok());
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(40);
  Eigen::VectorXd x(40);
  {
    const ScopedBlasThreads one(1);
    const ScopedBlasThreads nested(1);
    cholesky.solve(b.data(), x.data());
  }
  EXPECT_LT((A * x - b).norm() / b.norm(), kSolveTolerance);
  std::printf("BLAS thread control %s\n",
              ScopedBlasThreads::supported() ? "available (OpenBLAS)" : "not available");
}

}  // namespace
}  // namespace stickslip
