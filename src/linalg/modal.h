// Lowest eigenpairs of the generalised symmetric problem K φ = ω² M φ (K symmetric positive
// semi-definite, M symmetric positive definite), by shift-invert Lanczos (Spectra) over a sparse
// CHOLMOD factorisation of K − σM = G Gᵀ, in symmetric form: Lanczos on C = G⁻¹ M G⁻ᵀ, whose
// eigenvalues are ν = 1/(ω² − σ), with φ = G⁻ᵀ y. Modes are mass-normalised: φᵀ M φ = 1.
// K and M are stored with both triangles (full symmetric storage), as fe/ assembles them.
//
// The shift σ must lie below the lowest eigenvalue: K − σM is factorised by a sparse Cholesky
// (CHOLMOD), so an indefinite K − σM (σ above an eigenvalue, or K not positive semi-definite) is
// reported as kFactorizationFailed, never silently. With σ < 0 free (floating) bodies work: their
// rigid-body modes come out with ω² ≈ 0. The n lowest eigenpairs are returned, ω² ascending;
// each mode has φᵀ M φ = 1 and its sign fixed so that its largest-magnitude component is positive
// (on ties, within a relative 1e-4, the first such component: mirror-symmetric structures). Bad
// options or mismatched sizes throw InvalidInput; factorisation failure and non-convergence are
// returned in ModalSummary (with the converged pairs, if any).
#pragma once

#include <string>

#include <Eigen/Core>

#include "core/types.h"
#include "linalg/sparse_cholesky.h"

namespace stickslip {

struct ModalOptions {
  int num_modes = 10;         // n lowest eigenpairs wanted; 1 <= n < size
  double shift = -1.0;        // σ in (rad/s)²; must not be an eigenvalue. Negative default keeps
                              // K − σM positive definite for free (floating) bodies too.
  int subspace_size = 0;      // Lanczos basis size; 0 = automatic (max(2n+1, n+20), <= size)
  double tolerance = 1e-10;   // Spectra's relative convergence tolerance on the Ritz values
  int max_iterations = 1000;  // restarts
  // Vectors per Lanczos step. 1: Spectra's single-vector restarted Lanczos (each step two
  // memory-bound half solves). k >= 2: block Lanczos with full reorthogonalisation, k right-hand
  // sides per solve (supernodal BLAS-3, one BLAS thread), no restart: the basis grows to at most
  // max(subspace_size, 8 num_modes) + k vectors; if that does not converge, the single-vector
  // method is run. 0 = automatic: blocks of 8 for 20,000 rows and more, else single-vector.
  int block_size = 0;
};
void validate(const ModalOptions& options);  // throws InvalidInput naming field, value, rule

enum class ModalTermination { kConverged, kFactorizationFailed, kNotConverged };

struct ModalSummary {
  ModalTermination termination = ModalTermination::kNotConverged;
  int iterations = 0;  // restarts (single-vector Lanczos) or block steps (block Lanczos)
  int converged_modes = 0;
  int operations = 0;  // applications of G⁻¹ M G⁻ᵀ to a vector (one M product, two half solves)
  int block_size = 1;  // vectors per Lanczos step actually used (1: single-vector Lanczos)
  double factorization_seconds = 0;  // wall time of the CHOLMOD factorisation of K − σM
  double iteration_seconds = 0;      // wall time of the Lanczos iteration
  std::string message;
  bool ok() const { return termination == ModalTermination::kConverged; }
};

struct ModalResult {
  Eigen::VectorXd eigenvalues;  // ω², ascending, (rad/s)²
  Eigen::MatrixXd modes;        // size x n, mass-normalised, column j for eigenvalues(j)
  ModalSummary summary;
  Eigen::VectorXd frequencies_hz() const;  // sqrt(max(ω², 0)) / 2π
};

ModalResult solve_modes(const SparseMatrix& K, const SparseMatrix& M, const ModalOptions& options);

// The same eigen-solve with a factor the caller already holds: `factor` must be the successful
// Cholesky of K − σM with σ = options.shift (e.g. of K itself with shift 0, as Craig–Bampton has
// for K_ii), so no second factorisation is done; K is not needed. summary.factorization_seconds
// is 0. Throws InvalidInput for a failed factor or a size mismatch with M.
ModalResult solve_modes(const SparseCholesky& factor, const SparseMatrix& M,
                        const ModalOptions& options);

// Every eigenpair of K φ = ω² M φ for dense (or small sparse) symmetric K, M with M positive
// definite (K may be singular: free bodies give ω² ≈ 0; negative round-off is kept, not clamped):
// the same contract as solve_modes (ascending ω², ΦᵀMΦ = I, sign rule). Solved after a diagonal
// (Jacobi) scaling D = diag(M)^(-1/2) of both matrices, which leaves the eigenvalues unchanged and
// keeps the Cholesky of M accurate when DOFs of very different mass meet (a Craig–Bampton model:
// nodal masses of 1e-9 t beside unit modal masses). O(n³); for a few thousand rows at most.
// M not positive definite: kFactorizationFailed, no modes.
ModalResult dense_modes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M);
ModalResult dense_modes(const SparseMatrix& K, const SparseMatrix& M);

}  // namespace stickslip
