// Dense LU with partial pivoting of a real n x n matrix, P A = L U, through LAPACK (dgetrf,
// dgetrs: OpenBLAS's optimised kernels on Debian, twice as fast as Eigen's portable ones at the
// sizes of Newton's dR/dx), with the BLAS held to one thread during each call (threads on a
// 2-core machine only spin at these sizes; see linalg/blas_threads.h).
//
// compute(A) factors a copy of A, factor(A) factors A in place (A receives scratch storage of
// the same size: the caller's buffer is reused, nothing is copied); both return false when A is
// not finite or exactly singular (a zero pivot). rcond() estimates 1 / (‖A‖₁ ‖A⁻¹‖₁) (0 when
// singular; ‖A⁻¹‖₁ by the Hager–Higham method of LAPACK's dgecon and Eigen's rcond, a lower bound,
// with its solves through dgetrs) on first request only: the estimate costs about half a
// factorisation at Newton's sizes, so callers ask for it when they need it. solve(b) returns
// A⁻¹ b (only after a successful factorisation). Same contract as Eigen::PartialPivLU.
#pragma once

#include <complex>
#include <vector>

#include <Eigen/Core>

namespace stickslip {

class DenseLu {
 public:
  bool compute(const Eigen::MatrixXd& A);
  bool factor(Eigen::MatrixXd& A);
  bool factored() const { return ok_; }
  double rcond() const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  Eigen::VectorXd solve_with(char trans, const Eigen::VectorXd& b) const;  // 'N': A, 'T': Aᵀ
  double inverse_norm_estimate() const;                                    // of ‖A⁻¹‖₁
  Eigen::MatrixXd lu_;
  std::vector<int> pivots_;
  double anorm_ = 0.0;           // ‖A‖₁
  mutable double rcond_ = -1.0;  // < 0: not estimated yet
  bool ok_ = false;
};

// The same for a complex matrix (zgetrf, zgetrs; one BLAS thread): compute(A) returns false when
// A is not finite or exactly singular, and solve(b) then returns NaNs (as a singular Eigen LU
// would give infinities), so that an iterative solver using it as a preconditioner fails.
class ComplexDenseLu {
 public:
  bool compute(const Eigen::MatrixXcd& A);
  bool factored() const { return ok_; }
  Eigen::VectorXcd solve(const Eigen::VectorXcd& b) const;

 private:
  Eigen::MatrixXcd lu_;
  std::vector<int> pivots_;
  bool ok_ = false;
};

}  // namespace stickslip
