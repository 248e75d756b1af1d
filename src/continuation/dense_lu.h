// Dense LU with partial pivoting of a real n x n matrix, P A = L U, through LAPACK (dgetrf,
// dgetrs, dgecon: OpenBLAS's optimised kernels on Debian, several times faster than Eigen's
// portable ones at the sizes of Newton's dR/dx), with the BLAS held to one thread during each
// call (threads on a 2-core machine only spin at these sizes; see linalg/blas_threads.h).
//
// compute(A) factors a copy of A and returns false when A is not finite or exactly singular (a
// zero pivot); rcond() is LAPACK's estimate of 1 / (‖A‖₁ ‖A⁻¹‖₁) (0 when singular), solve(b)
// returns A⁻¹ b (only after a successful compute). Same contract as Eigen::PartialPivLU.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace stickslip {

class DenseLu {
 public:
  bool compute(const Eigen::MatrixXd& A);
  double rcond() const { return rcond_; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  Eigen::MatrixXd lu_;
  std::vector<int> pivots_;
  double rcond_ = 0.0;
  bool ok_ = false;
};

}  // namespace stickslip
