// Sparse Cholesky factorisation Pᵀ A P = L Lᵀ of a symmetric positive definite matrix A, for
// "factor once, solve many right-hand sides": X = A⁻¹ B.
//
// A is square, symmetric, stored with both triangles (as fe/ assembles K and M); only its lower
// triangle is read. CHOLMOD (SuiteSparse) computes a supernodal LLᵀ with a fill-reducing ordering
// (AMD, or METIS nested dissection when AMD fills in much; CHOLMOD's default strategy). Dense
// kernels go through the system BLAS (OpenBLAS on Debian with libopenblas0-pthread).
//
// A failed factorisation (A not positive definite, out of memory) is a numerical outcome, not an
// exception: ok() is false and message() says what happened (for a non-positive-definite A, the
// column of the permuted matrix where the factorisation broke down). A size mismatch in solve()
// or solving with a failed factor throws InvalidInput.
//
// Trailing ordering (factorize(A, last, ...)): the indices `last` are eliminated after all
// others, in the order given, so that P puts them at positions n − m .. n − 1 (m = |last|). Then
// for b supported on `last`, G⁻¹ b = L⁻¹ P b is zero in its first n − m entries and its last m
// entries are L_ll⁻¹ b_last with L_ll the trailing m x m block of L (one dense triangular solve;
// the sparse forward half solve is skipped). Craig–Bampton uses it for the constraint modes:
// K_ib is nonzero only in the interior rows coupled to the boundary.
//
// Not thread-safe: solve() reuses internal CHOLMOD workspace. Movable, not copyable.
#pragma once

#include <memory>
#include <span>
#include <string>

#include <Eigen/Core>

#include "core/types.h"

namespace stickslip {

// Size and cost of a factorisation, from the symbolic analysis only (cheap: no numbers).
struct CholeskyEstimate {
  double factor_nonzeros = 0;  // nnz(L)
  double flops = 0;            // floating-point operations of the numerical factorisation
  std::string ordering;        // the ordering CHOLMOD would select
};

// How factorize(A, last, ...) orders the indices `last`.
enum class LastOrdering {
  kAuto,    // at the end when the cost estimate below says that is cheaper, else as factorize(A)
  kAlways,  // at the end (tests, benchmarks)
  kNever,   // as factorize(A): CHOLMOD's own ordering
};

class SparseCholesky {
 public:
  // Symbolic analysis of A (square, lower triangle read) without factorising it.
  static CholeskyEstimate estimate(const SparseMatrix& A);

  SparseCholesky();
  explicit SparseCholesky(const SparseMatrix& A);  // calls factorize(A)
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Analyses and factorises A (any previous factor is dropped). Returns ok().
  bool factorize(const SparseMatrix& A);
  // The same with the trailing ordering of `last` (distinct indices in 0..n−1; see above).
  // kAuto compares the estimated flops of the two orderings (CHOLMOD's symbolic analysis, the
  // ordering of the other indices is CHOLMOD's own for A with `last` removed from it) for
  //   factorisation + trailing_solves · (forward over the trailing block + backward half solve)
  //                 + full_solves · (two half solves),
  // trailing_solves being right-hand sides supported on `last`. Returns ok(); num_last() tells
  // which ordering was used. Bad indices throw InvalidInput.
  bool factorize(const SparseMatrix& A, std::span<const int> last, LastOrdering mode,
                 double trailing_solves = 0, double full_solves = 0);

  bool ok() const;
  const std::string& message() const;  // "" when ok
  int size() const;                    // n of the factorised n x n matrix; 0 before factorize
  double factor_nonzeros() const;      // nnz(L), for diagnostics and benchmarks
  std::string ordering() const;        // ordering CHOLMOD selected: "AMD", "METIS", ...
  int num_last() const;  // m if `last` is ordered at the end (factorize with last), else 0

  // X = A⁻¹ B for B of size n x k (k >= 1 right-hand sides).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  // y = A⁻¹ x for raw arrays of length n (x and y may not alias). Used in inner loops.
  void solve(const double* x, double* y) const;
  // Half solves with the factor G = Pᵀ L of A = G Gᵀ (P the fill-reducing permutation):
  //   solve_lower: y = G⁻¹ x = L⁻¹ P x,   solve_upper: y = G⁻ᵀ x = Pᵀ L⁻ᵀ x,
  // so that A⁻¹ = G⁻ᵀ G⁻¹ and G⁻¹ B G⁻ᵀ is symmetric for symmetric B. Arrays of length n.
  void solve_lower(const double* x, double* y) const;
  void solve_upper(const double* x, double* y) const;
  // The same half solves for n x k blocks (k >= 1 columns at once: supernodal BLAS-3 kernels).
  Eigen::MatrixXd solve_lower(const Eigen::MatrixXd& B) const;
  Eigen::MatrixXd solve_upper(const Eigen::MatrixXd& B) const;
  // For num_last() = m > 0: the last m rows of G⁻¹ b for the n x k right-hand side b that is
  // zero outside `last` and has b(last[j], :) = B_last(j, :) (B_last: m x k). The first n − m
  // rows of G⁻¹ b are zero. Dense triangular solve with L's trailing block (BLAS dtrsm).
  Eigen::MatrixXd solve_lower_last(const Eigen::MatrixXd& B_last) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace stickslip
