// Static solves with a stiffness that its constraints do not hold: K symmetric positive
// semi-definite whose null space is rigid-body motion (a free–free body, a damper held only by its
// contacts, the interior of a Craig–Bampton body whose masters do not hold every rigid motion), M
// symmetric positive definite, both stored with both triangles (as fe/ assembles them):
//
//   x = K⁺ b := Σ_e φ_e φ_eᵀ b / λ_e   (e over the elastic modes, K φ = λ M φ, φᵀMφ = 1),
//
// i.e. the solution of K x = b − M Φ_0 Φ_0ᵀ b (b without its components on the rigid modes Φ_0,
// K Φ_0 = 0, Φ_0ᵀMΦ_0 = I) that is M-orthogonal to the rigid modes. The caller decides what a
// component of b on the rigid modes means (a resultant nothing holds: an error, or round-off) and
// what rigid motion to add.
//
// Computed from one CHOLMOD factor of A = K − σM, σ = −1e-10 · trace(K)/trace(M) (a tiny fraction
// of the mean eigenvalue: A's pivots stay far above round-off). A shift-invert eigen-solve over it
// (block Lanczos, 8 vectors per step, so that the repeated zero eigenvalue is found in full; dense
// when more than half of the modes are wanted) gives the rigid modes (eigenvalue below 1e-3 |σ|, or
// 1e-11 λ_max from the dense solve; set to exactly 0) and the num_elastic_modes lowest elastic
// ones. solve() refines X ← X + A⁻¹ R_d, R_d the residual b − K X without its components on the
// kept modes, the kept elastic components of X set exactly (φᵀb / λ): the error falls by |σ|/λ per
// step on every eigenvalue λ not kept (one to three steps in practice).
//
// factor_gives_back tells whether a factor of a matrix that may be singular can be trusted: a
// CHOLMOD factor of a numerically singular matrix can succeed (round-off makes the zero pivots
// positive) and then solves give components of the size 1/eps along the null space.
//
// Numerical outcomes (factorisation, eigen-solve, refinement not converged) are values: ok()
// and message(), FloatingSolveSummary. Size mismatches throw InvalidInput.
#pragma once

#include <string>

#include <Eigen/Core>

#include "core/types.h"
#include "linalg/modal.h"
#include "linalg/sparse_cholesky.h"

namespace stickslip {

// True when x = A⁻¹(A v) gives back a fixed pseudo-random v to 1e-6 (relative): a regular A gives
// it back to ~eps·cond(A).
bool factor_gives_back(const SparseCholesky& factor, const SparseMatrix& A);

struct FloatingFactorOptions {
  int num_elastic_modes = 0;  // lowest elastic modes kept beside the rigid ones (>= 0)
  ModalOptions modal;         // eigen-solve settings; num_modes and shift are set here
};

struct FloatingSolveSummary {
  bool converged = true;
  int steps = 0;          // refinement steps taken
  double residual = 0.0;  // ‖R_d‖ / ‖b‖ (Frobenius) at the end
};

class FloatingFactor {
 public:
  // Factorises K − σM and finds the kept modes. Returns ok(). K, M square of one size.
  bool compute(const SparseMatrix& K, const SparseMatrix& M, const FloatingFactorOptions& options);

  bool ok() const { return ok_; }
  bool factor_failed() const { return factor_failed_; }  // K − σM not positive definite
  const std::string& message() const { return message_; }
  double shift() const { return shift_; }  // σ, (rad/s)²
  int num_rigid() const { return num_rigid_; }
  // The kept modes: the num_rigid() rigid ones first (eigenvalue exactly 0), then the elastic
  // ones, ascending; size x kept, M-orthonormal.
  const Eigen::VectorXd& eigenvalues() const { return eigenvalues_; }
  const Eigen::MatrixXd& modes() const { return modes_; }
  Eigen::MatrixXd rigid_modes() const { return modes_.leftCols(num_rigid_); }
  const ModalSummary& modal_summary() const { return modal_; }

  // X = K⁺ B (size x k). A block that does not converge in 60 steps is returned as it stands
  // with summary->converged false (the first elastic eigenvalue not kept is too close to σ).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B, FloatingSolveSummary* summary = nullptr) const;

 private:
  SparseMatrix K_;
  SparseCholesky factor_;
  Eigen::MatrixXd modes_, M_modes_;  // Φ and M Φ
  Eigen::VectorXd eigenvalues_;
  ModalSummary modal_;
  std::string message_;
  double shift_ = 0.0;
  int num_rigid_ = 0;
  bool ok_ = false, factor_failed_ = false;
};

}  // namespace stickslip
