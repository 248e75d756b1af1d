// Full-model recovery: the linear harmonic response of one full FE body to given harmonic loads
// (docs/conventions.md, "Full-model recovery"). The loads are plain complex nodal forces
// (excitation plus the contact forces the nonlinear solve found, global axes, N); how they were
// obtained is not this module's business.
//
// Convention (docs/conventions.md): harmonic k of a real periodic signal has the complex amplitude
// X_k = a_k − i b_k, x(t) = Re Σ_k X_k e^{ikΩt}, Ω in rad/s; harmonic 0 is real (the mean).
// For harmonic k the free DOFs f (DofMap: clamped DOFs eliminated, x_c = 0) satisfy
//
//   D_k x_f = F_f,   D_k = K_ff − (kΩ)² M_ff + i kΩ C_ff,   C = αM + βK   (RayleighDamping),
//
// with K (N/m) and M (kg) as fe/assembly.h builds them (square 3 num_nodes, both triangles).
// The reaction loads at clamped DOFs are ignored; the returned displacement (m) is full size,
// 0 at the clamped DOFs.
//
// Solvers, both behind HarmonicSolver:
//  - DirectRecovery: exact. Harmonic 0 (or kΩ = 0) is the static solve K_ff x = F with a CHOLMOD
//    factor of K_ff computed once in the constructor; k ≥ 1 factorises the complex D_k with
//    UMFPACK (sparse LU) per call (all columns of one call share the factorisation).
//    A body that its clamps and supports do not hold (a damper, a body on springs or contacts
//    only: K_ff's factor fails or does not give back K_ff v, linalg/floating_factor.h) has rigid
//    modes Φ_0 (rigid_modes()). D_k, k ≥ 1, stays regular; the static solve has a solution only
//    for a load without resultant on Φ_0 (a larger one than round-off: kUnbalanced, NaN columns)
//    and is returned without rigid motion (x = K_ff⁺F, M-orthogonal to Φ_0): the rigid motion is
//    what the springs and contacts did, which the caller knows (add_rigid_motion).
//  - ModalRecovery: n modes of the clamped body (K_ff φ = ω² M_ff φ, φᵀM_ffφ = 1) computed once,
//    plus, by default, the static residual correction (the "missing-mass"/residual-flexibility
//    term; exact at kΩ = 0):
//      x = Σ_r φ_r φ_rᵀF / (ω_r² − (kΩ)² + i kΩ c_r) + [K⁻¹F − Σ_r φ_r φ_rᵀF / ω_r²],
//      c_r = α + β ω_r².
//    Without the correction it is plain mode superposition (ANSYS MSUP without residual vectors,
//    CalculiX's *STEADY STATE DYNAMICS). The modes and the CHOLMOD factor of K_ff are computed once
//    and reused for every load, harmonic and frequency. A body that its clamps and supports do
//    not hold keeps its r rigid modes (ω_r = 0, c_r = α: h_r = 1/(−(kΩ)² + ikΩα)) beside n
//    elastic ones; K⁻¹ is then K_ff⁺ (no rigid part), and harmonic 0 is treated as in
//    DirectRecovery (resultant checked, no rigid motion, rigid_modes()). Choose n at a gap of the
//    spectrum: a truncation inside a group of repeated frequencies (symmetric bodies) depends on
//    the arbitrary basis the eigen-solver picked for that eigenspace (and so differs between
//    codes).
// A failed setup (factorisation of K_ff or eigen-solve) is a numerical outcome: ok() false,
// message() says why; solve() on a failed object, and bad sizes or options, throw InvalidInput.
// A singular D_k at solve time (kΩ exactly at an undamped natural frequency: no damping and
// h_r = 1/0) is a numerical outcome too, reported per call in a RecoverySummary: the columns of
// that harmonic are NaN (never a finite wrong answer), the other harmonics are solved.
#pragma once

#include <complex>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "fe/dof_map.h"
#include "linalg/modal.h"

namespace stickslip {

// C = alpha M + beta K (docs/conventions.md; the thesis: alpha = 5 1/s, beta = 0).
struct RayleighDamping {
  double alpha = 0.0;  // 1/s, >= 0
  double beta = 0.0;   // s, >= 0
};
void validate(const RayleighDamping& damping);  // throws InvalidInput naming field and rule

// A complex harmonic amplitude of a concentrated force at one node (global axes, N).
struct ComplexNodalForce {
  int node = 0;  // node index (not id)
  Eigen::Vector3cd force = Eigen::Vector3cd::Zero();
};
// Global complex load vector, size 3 num_nodes (repeats add up); InvalidInput for a node out of
// range.
Eigen::VectorXcd complex_nodal_force_vector(int num_nodes,
                                            std::span<const ComplexNodalForce> forces);

// Outcome of one solve (STYLE.md's second error channel). Pass a summary to learn whether every
// harmonic was solved; without one, unsolved columns are still NaN.
enum class RecoveryTermination {
  kSuccess,     // every harmonic solved
  kSingular,    // D_k singular for the harmonics listed (undamped resonance): their columns NaN
  kFailure,     // the sparse factorisation failed otherwise (e.g. out of memory): columns NaN
  kUnbalanced,  // a static load with a resultant on rigid motion nothing holds: columns NaN
};
struct RecoverySummary {
  RecoveryTermination termination = RecoveryTermination::kSuccess;
  std::vector<int> failed_harmonics;  // harmonic numbers k whose columns are NaN
  std::string message;                // empty on success
  bool ok() const { return termination == RecoveryTermination::kSuccess; }
};

// Solves D_k x = F for one harmonic. F: num_dofs x m complex (m load cases at the same kΩ);
// returns num_dofs x m, clamped rows 0. harmonic >= 0, omega >= 0 (rad/s).
class HarmonicSolver {
 public:
  virtual ~HarmonicSolver() = default;
  // summary (optional) is reset and filled; see RecoverySummary.
  virtual Eigen::MatrixXcd solve(const Eigen::MatrixXcd& F, int harmonic, double omega,
                                 RecoverySummary* summary = nullptr) const = 0;
  // Column j of `loads` at harmonic harmonics[j] (sizes checked by harmonic_response). The
  // default calls solve() per column; ModalRecovery does all columns in one pass.
  virtual Eigen::MatrixXcd solve_harmonics(const Eigen::MatrixXcd& loads,
                                           std::span<const int> harmonics, double omega,
                                           RecoverySummary* summary = nullptr) const;
  virtual int num_dofs() const = 0;
  // The rigid-body modes the clamps and supports do not hold: num_dofs x r, M-orthonormal,
  // constrained rows 0; no columns for a held body. Harmonic 0 comes without motion along them.
  virtual Eigen::MatrixXd rigid_modes() const { return Eigen::MatrixXd(num_dofs(), 0); }
  virtual bool ok() const = 0;
  virtual const std::string& message() const = 0;
};

// Response to several harmonics: column j of `loads` is harmonic harmonics[j] (num_dofs x nh);
// returns num_dofs x nh. Harmonic 0's load must be real (imaginary part <= 1e-12 max|F|, else
// InvalidInput) and so is its response. A harmonic that cannot be solved (singular D_k) gives a
// NaN column and is reported in *summary (if given): check summary->ok().
Eigen::MatrixXcd harmonic_response(const HarmonicSolver& solver, const Eigen::MatrixXcd& loads,
                                   std::span<const int> harmonics, double omega,
                                   RecoverySummary* summary = nullptr);

class DirectRecovery final : public HarmonicSolver {
 public:
  DirectRecovery(const SparseMatrix& K, const SparseMatrix& M, const DofMap& dofs,
                 RayleighDamping damping);
  ~DirectRecovery() override;
  Eigen::MatrixXcd solve(const Eigen::MatrixXcd& F, int harmonic, double omega,
                         RecoverySummary* summary = nullptr) const override;
  int num_dofs() const override { return dofs_.num_dofs(); }
  Eigen::MatrixXd rigid_modes() const override;
  // False if the static factorisation failed (then message()). A singular D_k in solve()
  // (UMFPACK finds a zero pivot: undamped resonance) is reported in the summary, NaN columns.
  bool ok() const override;
  const std::string& message() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  DofMap dofs_;
};

struct ModalRecoveryOptions {
  int num_modes = 100;              // n; 1 <= n < number of free DOFs
  bool residual_correction = true;  // add the static residual term
  ModalOptions modal;               // eigen-solve settings; modal.num_modes is ignored
  // Full DOFs that carry the loads (contact and excitation DOFs), optional. When given, the
  // residual attachment modes R = K_ff⁻¹B − Φ Ω⁻² ΦᵀB (B selects these DOFs; num_free x |B|)
  // are computed once, and a load supported on these DOFs costs two dense products
  // (x = Φ (h ∘ Φ_Bᵀ F_B) + R F_B) instead of a sparse triangular solve per load case. Loads with
  // entries elsewhere use the factor as usual. Constrained DOFs in the list are ignored.
  std::vector<int> load_dofs;
  // Threads for the per-point products with Φ and R (rows split; memory bound, so 2 is where
  // a two-channel machine saturates). 0 = one per hardware thread.
  int num_threads = 0;
};
void validate(const ModalRecoveryOptions& options);

class ModalRecovery final : public HarmonicSolver {
 public:
  ModalRecovery(const SparseMatrix& K, const SparseMatrix& M, const DofMap& dofs,
                RayleighDamping damping, const ModalRecoveryOptions& options = {});
  ~ModalRecovery() override;
  Eigen::MatrixXcd solve(const Eigen::MatrixXcd& F, int harmonic, double omega,
                         RecoverySummary* summary = nullptr) const override;
  Eigen::MatrixXcd solve_harmonics(const Eigen::MatrixXcd& loads, std::span<const int> harmonics,
                                   double omega, RecoverySummary* summary = nullptr) const override;
  int num_dofs() const override { return dofs_.num_dofs(); }
  Eigen::MatrixXd rigid_modes() const override;
  bool ok() const override;
  const std::string& message() const override;

  // Modal form of the response, for fields linear in x (stresses, strains): with the loads
  // supported on options.load_dofs B (InvalidInput otherwise, or if load_dofs was not given),
  //   x_k = Σ_c basis_column(c) · coordinates(c, k),
  // c over the n modes (coordinate h_r(kΩ) φ_rᵀF_k) and then, with the residual correction,
  // the |B| attachment modes (coordinate F_k at that DOF). Columns k as in `harmonics`.
  int num_basis_columns() const;
  Eigen::MatrixXcd coordinates(const Eigen::MatrixXcd& loads, std::span<const int> harmonics,
                               double omega) const;
  Eigen::VectorXd basis_column(int c) const;  // full size (num_dofs), clamped entries 0

  // The one-off work, for diagnostics and benchmarks.
  const Eigen::VectorXd& eigenvalues() const;  // ω_r², (rad/s)², ascending
  const Eigen::MatrixXd& modes() const;        // num_free x n, mass-normalised (free DOFs)
  const ModalSummary& modal_summary() const;
  double setup_seconds() const;  // modes + Cholesky factor of K_ff

 private:
  Eigen::MatrixXcd solve_columns(const Eigen::MatrixXcd& F, const Eigen::VectorXd& w,
                                 std::span<const int> harmonics, RecoverySummary* summary) const;
  Eigen::MatrixXd static_solve(const Eigen::MatrixXd& B) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  DofMap dofs_;
};

// Adds to x (num_dofs) the rigid motion Φ_0 a that brings x closest to `target` at `dofs`
// (least squares, min ‖a‖ for motions the DOFs do not see: those stay 0): the rigid motion of a
// body recovered without it, from the reduced response at its master DOFs, which carries it.
// Returns a (r). rigid_modes: num_dofs x r (HarmonicSolver::rigid_modes); target: one value per
// entry of dofs. Complex, so that a dynamic harmonic could use it too (recovery does not).
Eigen::VectorXcd add_rigid_motion(const Eigen::MatrixXd& rigid_modes, std::span<const int> dofs,
                                  const Eigen::VectorXcd& target, Eigen::Ref<Eigen::VectorXcd> x);

// Expansion through a reduction basis (Craig–Bampton): x = T q per harmonic. T is dense,
// num_dofs x n_r with rows in the full DOF numbering (as reduction/craig_bampton.h returns it;
// constrained rows zero); q is n_r x nh (columns = harmonics). Returns num_dofs x nh.
Eigen::MatrixXcd expand_reduced_response(const Eigen::MatrixXd& T, const Eigen::MatrixXcd& q);
// The same with T's rows on the free DOFs only (num_free x n_r): constrained rows of the result 0.
Eigen::MatrixXcd expand_reduced_response(const Eigen::MatrixXd& T_free, const DofMap& dofs,
                                         const Eigen::MatrixXcd& q);

// Difference of two full responses a, b (num_dofs x nh, same harmonic columns) at chosen DOFs
// (e.g. the master DOFs), per harmonic column j, b being the reference:
//   max_relative[j] = max_i |a_ij − b_ij| / max_i |b_ij|,
//   rms_relative[j] = sqrt(Σ_i |a_ij − b_ij|²) / sqrt(Σ_i |b_ij|²)   (i over `dofs`).
// A zero reference column gives 0 if a's column is also 0 there, else +infinity.
struct ResponseDifference {
  std::vector<double> max_relative;
  std::vector<double> rms_relative;
  std::vector<double> max_absolute;  // max |a − b| over the DOFs (meaningful where b = 0)
};
ResponseDifference compare_responses(const Eigen::MatrixXcd& a, const Eigen::MatrixXcd& b,
                                     std::span<const int> dofs);

}  // namespace stickslip
