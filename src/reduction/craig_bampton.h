// Craig–Bampton reduction of one linear body onto boundary (master) DOFs b and the n lowest
// fixed-interface modes (R. R. Craig, M. C. C. Bampton, AIAA J. 6(7), 1968):
//
//   x = T q,  q = [x_b; η],  with the DOFs split into constrained c (clamped: x_c = 0,
//   eliminated), boundary b and interior i (all the others):
//
//       [x_b]   [ I    0  ] [x_b]        Φ_c = −K_ii⁻¹ K_ib           (constraint modes)
//       [x_i] = [ Φ_c  Φ_n] [ η ],       K_ii Φ_n = M_ii Φ_n Ω²,  Φ_nᵀ M_ii Φ_n = I
//       [x_c]   [ 0    0  ]              (the n lowest fixed-interface modes)
//
//   K_r = TᵀKT = [K_bb + K_bi Φ_c, 0; 0, Ω²],   M_r = TᵀMT = [M_bb + ..., M_bη; M_ηb, I].
//
// Inputs: K, M (n x n, symmetric, full storage with both triangles, SI units), the constrained
// DOFs and the boundary DOFs (0-based DOF numbers, 3·node + direction; unique, disjoint, any
// order: reduced DOF k < n_b is boundary_dofs[k]). The reduction sees matrices and a DOF
// partition, never a mesh. Output: dense K_r, M_r (size n_b + n_modes, boundary DOFs first, then
// modes by ascending frequency), what each reduced DOF is, the fixed-interface eigenvalues and,
// on request, the basis T (n x (n_b + n_modes), rows in the full DOF numbering, constrained rows
// zero) for the expansion x = T q.
//
// Floating interior. When the boundary and constrained DOFs do not hold every rigid motion of the
// body (no masters: a free–free body; masters on one node or on a line; a damper whose masters
// are its contact nodes in some directions only), K_ii is singular: its null space is the body's
// rigid motions that leave the boundary at rest. Then the rigid modes of the interior are kept as
// generalised coordinates beside the num_modes lowest elastic fixed-interface modes (n_modes =
// n_rigid + num_modes, at most n_i; their eigenvalues are exactly 0 in K_r), and the constraint
// modes are the particular solution Φ_c = −K_ii⁺ K_ib M-orthogonal to them (K_ii Φ_c = −K_ib has
// solutions: K_ib's columns are orthogonal to null(K_ii)). T then spans the body's rigid motions
// and its static response to any boundary load that the free body can carry (self-equilibrated
// loads, with the rigid modes free), and K_r, M_r keep the form above, so nothing downstream
// changes. Computed from one factor of K_ii − σM_ii (σ < 0, a tiny fraction of the mean
// eigenvalue): the shift-invert eigen-solve finds the rigid modes as its lowest (block Lanczos, so
// that the repeated zero eigenvalue is found in full), and Φ_c is refined with it in the
// complement of the kept modes (convergence |σ|/λ per step on every eigenvalue λ not kept). The
// factor of K_ii is taken as singular when it fails or when it does not give back a test vector
// (x = K_ii⁻¹(K_ii v) ≠ v to 1e-6: round-off made the zero pivots positive).
//
// Cost: one sparse Cholesky of K_ii (SparseCholesky, CHOLMOD) solving all n_b constraint modes
// in blocks of `block_size` right-hand sides (only the backward half solves when the interior DOFs
// coupled to the boundary are ordered last, see coupled_last), one shift-invert Lanczos solve of
// (K_ii, M_ii) over that same factor (shift 0, the default here; another modal.shift factorises
// K_ii − σM_ii), one pass of M_ii over Φ_c and dense products of size n_b x n_i x n_b (BLAS). No n
// x n dense matrix is formed. Bad input throws InvalidInput; a failed factorisation or eigen-solve
// is reported in the summary (no exception).
#pragma once

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "linalg/modal.h"
#include "linalg/sparse_cholesky.h"
#include "reduction/reduced_body.h"

namespace stickslip {

struct CraigBamptonOptions {
  int num_modes = 60;      // fixed-interface modes kept, <= interior DOFs (all of them: a dense
                           // eigen-solve, the exact model); 0 = Guyan (static) reduction
  int block_size = 128;    // constraint modes solved per block (memory ~ 16 n_i block_size bytes)
  bool keep_basis = true;  // keep T in the result (n x (n_b + num_modes) doubles)
  // Order the interior DOFs coupled to the boundary (rows of K_ib with entries) last in the
  // Cholesky of K_ii: G⁻¹K_ib is then Z in the trailing rows only, the constraint modes need only
  // the backward half solves, and K_bi Φ_c = −ZᵀZ. kAuto: when the flop estimate says it pays.
  LastOrdering coupled_last = LastOrdering::kAuto;
  // K, M are the real form [A −B; B A] of a complex Hermitian pair (2n square; see
  // reduction/cyclic_craig_bampton.h) and boundary_dofs = {b, n + b} (the second half the first
  // plus n), the constrained DOFs likewise: the constraint modes of the second half are J times
  // those of the first, J(x; y) = (−y; x) (K commutes with J), and only the first half is solved
  // for. Otherwise InvalidInput. Ignored for a floating interior.
  bool hermitian_real_form = false;
  // Fixed-interface eigen-solve settings; modal.num_modes is ignored. Shift 0 (default): the
  // Lanczos reuses the Cholesky of K_ii (positive definite once the interior is held); any other
  // shift costs a second factorisation, of K_ii − σM_ii.
  ModalOptions modal = [] {
    ModalOptions m;
    m.shift = 0.0;
    return m;
  }();
};
void validate(const CraigBamptonOptions& options);  // throws InvalidInput naming field and rule

enum class CraigBamptonTermination {
  kSuccess,
  kFactorizationFailed,  // neither K_ii nor K_ii − σM_ii positive definite: K is not
                         // positive semi-definite (or M not positive definite)
  kEigenSolveFailed,     // the fixed-interface modal solve failed (see message)
};

struct CraigBamptonSummary {
  CraigBamptonTermination termination = CraigBamptonTermination::kSuccess;
  std::string message;  // empty on success
  int num_dofs = 0;
  int num_constrained = 0;
  int num_boundary = 0;
  int num_interior = 0;
  int num_modes = 0;                // fixed-interface modes kept, rigid ones included
  int num_rigid_modes = 0;          // rigid modes of a floating interior (the first num_modes)
  double floating_shift = 0.0;      // σ of a floating interior's factor K_ii − σM_ii, (rad/s)²
  int refinement_steps = 0;         // most refinement steps of its constraint modes (a block)
  double factor_nonzeros = 0.0;     // nnz of the Cholesky factor of K_ii
  int coupled_last = 0;             // interior DOFs ordered last (0: CHOLMOD's own ordering)
  double seconds_factor = 0.0;      // partition and Cholesky of K_ii
  double seconds_constraint = 0.0;  // constraint-mode solves
  double seconds_modes = 0.0;       // fixed-interface eigen-solve
  double seconds_projection = 0.0;  // reduced matrices and T
  // CPU seconds (user + system) of the process during each phase, all its threads: on a shared
  // machine a steadier measure of the cost than the wall times above.
  double cpu_seconds_factor = 0.0, cpu_seconds_constraint = 0.0, cpu_seconds_modes = 0.0,
         cpu_seconds_projection = 0.0;
  ModalSummary modal;  // the fixed-interface eigen-solve (its own factorisation, iterations)
  bool ok() const { return termination == CraigBamptonTermination::kSuccess; }
};

struct CraigBamptonResult {
  ReducedBody body;                  // K_r, M_r (symmetric), reduced DOF map
  Eigen::MatrixXd T;                 // n x (n_b + n_modes) if options.keep_basis, else empty
  Eigen::VectorXd mode_eigenvalues;  // Ω² of the kept fixed-interface modes, (rad/s)², ascending
  std::vector<int> interior_dofs;    // the interior DOFs i, ascending
  CraigBamptonSummary summary;
};

CraigBamptonResult craig_bampton(const SparseMatrix& K, const SparseMatrix& M,
                                 std::span<const int> constrained_dofs,
                                 std::span<const int> boundary_dofs,
                                 const CraigBamptonOptions& options);

// The reduced DOFs of a Craig–Bampton body: the boundary DOFs (physical, in the given order),
// then one modal DOF per fixed-interface mode (eigenvalues Ω², their frequencies in Hz).
std::vector<ReducedDof> craig_bampton_dofs(std::span<const int> boundary_dofs,
                                           const Eigen::VectorXd& mode_eigenvalues);

}  // namespace stickslip
