#include "linalg/sparse_ops.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/errors.h"

namespace stickslip {
namespace {

// Random sparse matrix with about `density` of its entries set, seeded.
SparseMatrix random_sparse(int rows, int cols, double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::bernoulli_distribution keep(density);
  std::vector<Triplet> triplets;
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) {
      if (keep(rng)) triplets.emplace_back(i, j, value(rng));
    }
  }
  SparseMatrix A(rows, cols);
  A.setFromTriplets(triplets.begin(), triplets.end());
  return A;
}

void expect_block_matches_dense(const SparseMatrix& A, const std::vector<int>& rows,
                                const std::vector<int>& cols) {
  const SparseMatrix B = submatrix(A, rows, cols);
  ASSERT_EQ(B.rows(), static_cast<Eigen::Index>(rows.size()));
  ASSERT_EQ(B.cols(), static_cast<Eigen::Index>(cols.size()));
  const Eigen::MatrixXd dense = Eigen::MatrixXd(A);
  const Eigen::MatrixXd block = Eigen::MatrixXd(B);
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t j = 0; j < cols.size(); ++j) {
      EXPECT_EQ(block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)),
                dense(rows[i], cols[j]))
          << "entry (" << i << ", " << j << ")";
    }
  }
  // Sorted inner indices in every column: the result is a valid Eigen matrix for other ops.
  for (Eigen::Index j = 0; j < B.outerSize(); ++j) {
    for (int p = B.outerIndexPtr()[j] + 1; p < B.outerIndexPtr()[j + 1]; ++p) {
      EXPECT_LT(B.innerIndexPtr()[p - 1], B.innerIndexPtr()[p]);
    }
  }
}

TEST(Submatrix, AscendingIndexListsGiveTheDenseBlock) {
  const SparseMatrix A = random_sparse(40, 30, 0.2, 7);
  expect_block_matches_dense(A, {0, 3, 4, 10, 39}, {1, 2, 29});
}

TEST(Submatrix, UnorderedIndexListsFollowTheListOrder) {
  const SparseMatrix A = random_sparse(40, 30, 0.3, 11);
  expect_block_matches_dense(A, {39, 3, 17, 0, 8, 21}, {5, 0, 28, 13});
}

TEST(Submatrix, PartitionOfSymmetricMatrixReassemblesIt) {
  SparseMatrix A = random_sparse(25, 25, 0.2, 3);
  A = SparseMatrix(A + SparseMatrix(A.transpose()));
  const std::vector<int> inner = {0, 2, 3, 5, 7, 8, 9, 11, 13, 14, 15, 16, 18, 20, 21, 23, 24};
  const std::vector<int> boundary = {1, 4, 6, 10, 12, 17, 19, 22};
  const Eigen::MatrixXd Kii = Eigen::MatrixXd(submatrix(A, inner, inner));
  const Eigen::MatrixXd Kib = Eigen::MatrixXd(submatrix(A, inner, boundary));
  const Eigen::MatrixXd Kbi = Eigen::MatrixXd(submatrix(A, boundary, inner));
  EXPECT_EQ((Kii - Kii.transpose()).norm(), 0.0);
  EXPECT_EQ((Kib - Kbi.transpose()).norm(), 0.0);
  EXPECT_EQ(submatrix(A, inner, inner).nonZeros() + submatrix(A, inner, boundary).nonZeros() +
                submatrix(A, boundary, inner).nonZeros() +
                submatrix(A, boundary, boundary).nonZeros(),
            A.nonZeros());
}

TEST(Submatrix, EmptyListsGiveEmptyBlocks) {
  const SparseMatrix A = random_sparse(10, 10, 0.5, 5);
  const SparseMatrix B = submatrix(A, std::vector<int>{}, std::vector<int>{1, 2});
  EXPECT_EQ(B.rows(), 0);
  EXPECT_EQ(B.cols(), 2);
  EXPECT_EQ(B.nonZeros(), 0);
}

TEST(Submatrix, BadIndexListsThrow) {
  const SparseMatrix A = random_sparse(10, 8, 0.5, 5);
  EXPECT_THROW(submatrix(A, std::vector<int>{0, 10}, std::vector<int>{0}), InvalidInput);
  EXPECT_THROW(submatrix(A, std::vector<int>{-1}, std::vector<int>{0}), InvalidInput);
  EXPECT_THROW(submatrix(A, std::vector<int>{0}, std::vector<int>{8}), InvalidInput);
  EXPECT_THROW(submatrix(A, std::vector<int>{2, 2}, std::vector<int>{0}), InvalidInput);
  EXPECT_THROW(submatrix(A, std::vector<int>{0}, std::vector<int>{3, 3}), InvalidInput);
}

}  // namespace
}  // namespace stickslip
