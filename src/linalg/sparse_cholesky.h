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
// Not thread-safe: solve() reuses internal CHOLMOD workspace. Movable, not copyable.
#pragma once

#include <memory>
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

  bool ok() const;
  const std::string& message() const;  // "" when ok
  int size() const;                    // n of the factorised n x n matrix; 0 before factorize
  double factor_nonzeros() const;      // nnz(L), for diagnostics and benchmarks
  std::string ordering() const;        // ordering CHOLMOD selected: "AMD", "METIS", ...

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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace stickslip
