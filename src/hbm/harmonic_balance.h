// Condensed multi-harmonic balance on the contact DOFs (docs/conventions.md, "The condensed
// harmonic balance").
//
// Linear model (LinearModel): ndof master DOFs x, nm modes, mass-normalised (Φᵀ M Φ = I), modal
// equations q̈_r + c_r q̇_r + ω_r² q_r = φ_rᵀ F. Per harmonic k the dynamic flexibility is
//   D_k⁻¹ = Φ diag(h_k) Φᵀ,  h_{k,r}(Ω) = 1 / (ω_r² − (kΩ)² + i kΩ c_r).
// Modal damping from Rayleigh C = αM + βK: c_r = α + β ω_r²; from a damping ratio ζ: c_r = 2ζω_r.
// Non-proportional damping: LinearModel.modal_damping_matrix C_m = ΦᵀCΦ (nm x nm, symmetric,
// positive semi-definite), when given, replaces the diagonal c_r and the flexibility becomes dense:
//   D_k⁻¹ = Φ H_k Φᵀ,  H_k(Ω) = (diag(ω_r²) − (kΩ)² I + i kΩ C_m)⁻¹  (k ≥ 1; complex symmetric),
// harmonic 0 is undamped, H_0 = diag(1/ω_r²) either way. Everything below that is written with
// diag(h_k) then reads H_k, and dH_k/dΩ = −H_k (−2k²Ω I + i k C_m) H_k. H_k is one operator
// (hbm/modal_flexibility.h) whose implementation (diagonal, state space, impedance LU) is chosen
// at construction. Two ways to apply a dense H_k (HarmonicBalanceOptions.damping_matrix_method):
//   state space (default): the damped modal problem is diagonalised once, at construction. Its
//     elastic part (ω_r² > kRigidModeRatio max ω²) in y = [diag(ω) q; q̇] is ẏ = A y with
//     A = [0 diag(ω); −diag(ω) −C_ee]; the 2·ne eigenpairs A y_j = s_j y_j, normalised so that
//     y_jᵀ diag(I, −I) y_j = 1, give with ψ_j = diag(ω)⁻¹ y_j,top
//       H_k(Ω) = Σ_j ψ_j ψ_jᵀ (−s_j) / (i kΩ − s_j)  (+ the rigid-body block, below),
//     equivalently Σ_j ψ_j ψ_jᵀ / (a_j (i kΩ − s_j)), a_j = ψ_jᵀ (2 s_j I + C_m) ψ_j for ψ_j of
//     any scale. G_k, dG_k/dΩ, u_lin, du_lin/dΩ and the master response are then weighted sums
//     over 2·ne vectors, like the diagonal path (about twice its work per Ω). Rigid-body modes
//     (ω_r² ≤ kRigidModeRatio max ω²) must not be coupled to the elastic ones by C_m (else: LU
//     path); their block is diagonalised by a rotation among themselves, h = 1/(−(kΩ)² + i kΩ c).
//     Eigenvalues that the eigenvectors cannot separate (repeated modes, e.g. identical bodies) are
//     grouped and their invariant subspace re-diagonalised. When the eigenvector basis is
//     ill-conditioned (defective or nearly defective: critical damping of some mode, eigenvalues
//     near the real axis coupled to their conjugates), or a check of the expansion against the LU
//     at probe frequencies fails, the LU path is used instead: damping_matrix_note() says why.
//   impedance LU: a complex LU of the nm x nm modal impedance per harmonic and Ω (O(nm³) per Ω).
//
// Contact pairs: pair p joins node A (DOFs dofs_a) and node B (dofs_b; either may be empty =
// ground) through a NonlinearElement of dimension m_p with frame R_p (m_p x k, k = DOFs per node):
//   u_p = R_p (x_A − x_B);  the element force f_p acts on B as +R_pᵀ f_p, on A as −R_pᵀ f_p.
// Stacking all pairs, u = B x (nu = Σ m_p rows) and the contact force on the structure is −Bᵀ f.
// No pairs at all is allowed: a linear structure (nu = 0, size() = 0, R empty; master_response
// gives the linear forced response). A stepped sweep solves it; arc-length has nothing to follow.
//
// Excitation: F(t) = Re Σ_k F_k e^{ikΩt} (complex nodal forces per harmonic; for k = 0 the real
// part is the static load). Linear response x_lin,k = D_k⁻¹ F_k, u_lin,k = B x_lin,k.
//
// Unknowns x (size nu·nc, nc = coefficients of the unknown HarmonicSet S): the real Fourier
// coefficients of u, signal-major (fourier.h): entry r·nc + c is coefficient c of contact row r
// (pair p's rows are r_p .. r_p + m_p − 1, so each pair's unknowns are contiguous).
//   coupled:   S = {0} ∪ dynamic harmonics; harmonic 0 solved with the others.
//   uncoupled: S = dynamic harmonics; first the static problem u0 = u_lin,0 − G_0 f(u0) is solved
//              (static element laws along the loading path below), then u0 is frozen as the mean
//              of u(t) in the AFT and f_0 is frozen for the recovery; the harmonic-0 balance is
//              not part of R.
// Static loading path (both formulations solve it; coupled starts its harmonic balance from it):
// a load factor λ from 0 to 1 multiplies u_lin,0 (static loads, harmonic-0 excitation, the loads
// balancing typed preloads) and the typed preloads N0 themselves; gaps and interferences are
// geometry, there at λ = 0. Each step λ_a → λ_b solves the static problem at λ_b with each
// friction element's tangential spring anchored where λ_a left it, τ = radial return of
// kt (u_t − s_a) onto |τ| ≤ μN (backward Euler: exact for slip of fixed direction); stick keeps
// the anchor s, slip moves it to u_t − τ/kt, lift-off to u_t (the spring released). A point open at
// λ_a and closed at λ_b closes in between: the step is cut at the earliest such touchdown, where
// its normal force reaches 0 along the path's tangent at λ_a (every element in its state there:
// exact up to the first change of state), so it starts to stick from where it touched.
// HarmonicBalanceOptions.static_increments sets the steps (automatic: one proportional step unless
// a friction element has an initial gap or interference: with none the static problem is
// positively homogeneous and one step is the incremental path exactly). The anchors s the path
// ends with carry each point's tangential state into the AFT: friction elements march u − (s, 0)
// (pair_offset), so the cycle starts from the static τ0 at u0, not from the virgin state at u0.
//
// Residual (units m), per harmonic k of S with complex U_k = a_k − i b_k, F_k = fa_k − i fb_k
// (AFT force coefficients) and G_k = G_r + i G_i = B D_k⁻¹ Bᵀ:
//   U_k − u_lin,k + G_k F_k = 0, split into real rows
//     R_a = a_k − Re u_lin,k + G_r fa_k + G_i fb_k
//     R_b = b_k + Im u_lin,k − G_i fa_k + G_r fb_k
//   and for k = 0: R_0 = a_0 − u_lin,0 + G_0 f_0.
// dR/dx = I + 𝔾 ∂F/∂x (∂F/∂x block-diagonal per pair, exact through the AFT) and
// dR/dΩ = (∂𝔾/∂Ω) F − ∂u_lin/∂Ω, analytic (the element laws are rate-independent).
// Harmonic 0 and rigid-body modes (ω_r² ≤ kRigidModeRatio max ω²; bodies held by springs or
// contacts only): G_0 does not exist. With a diagonal K_s > 0 on the contact rows (each row's
// element tangent at rest, or a positive stand-in) the static balance is written in the shifted
// form
//   R_0 = u_0 − ũ_lin,0 + G̃_0 (f_0 − K_s u_0),  G̃_0 = Ψ H̃_0 Ψᵀ,  ũ_lin,0 = Ψ H̃_0 Φᵀ F_0,
//   H̃_0 = (Ω² + Ψᵀ K_s Ψ)⁻¹ on the modes the contact rows see,
// exact for any K_s (K_s u added on both sides of K x = F − Bᵀ f). Rigid motions that move no
// contact row are left out of H̃_0, and a static load with a resultant on them is refused
// (InvalidInput: nothing holds the body). Without rigid-body modes harmonic 0 is G_0 = Ψ
// diag(1/ω²) Ψᵀ as above.
//
// Recovery of every master DOF: x_k = Φ diag(h_k) (Φᵀ F_k − Ψᵀ F_k^c), Ψ = BΦ (H_k when the
// modal damping matrix is given).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "contact/nonlinear_element.h"
#include "continuation/newton.h"
#include "continuation/parametrized_system.h"
#include "hbm/aft.h"
#include "hbm/fourier.h"
#include "hbm/modal_flexibility.h"
#include "hbm/travelling_wave.h"
#include "linalg/dense_lu.h"

namespace stickslip {

struct LinearModel {
  Eigen::VectorXd omega2{};         // ω_r², (rad/s)², ≥ 0, size nm
  Eigen::MatrixXd Phi{};            // ndof x nm, mass-normalised
  Eigen::VectorXd modal_damping{};  // c_r, 1/s, ≥ 0, size nm (may be empty when the matrix is set)
  Eigen::MatrixXd modal_damping_matrix{};  // optional nm x nm ΦᵀCΦ (symmetric, PSD); when
                                           // non-empty it replaces modal_damping
};
void validate(const LinearModel& model);

Eigen::VectorXd rayleigh_modal_damping(const Eigen::VectorXd& omega2, double alpha, double beta);
Eigen::VectorXd modal_damping_from_ratio(const Eigen::VectorXd& omega2, double zeta);
// All modes of dense symmetric (K, M), M positive definite; damping c_r = α + β ω_r².
LinearModel linear_model_from_matrices(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                       double alpha, double beta);
// All modes of dense symmetric (K, M) with a general dense damping matrix C (ndof x ndof,
// symmetric, PSD): modal_damping_matrix = ΦᵀCΦ (symmetrised), modal_damping = its diagonal
// (informative only; the matrix is used).
LinearModel linear_model_from_matrices(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                       const Eigen::MatrixXd& C);

struct ContactPair {
  std::vector<int> dofs_a{};  // k master-DOF indices of node A; empty = ground
  std::vector<int> dofs_b{};  // k master-DOF indices of node B; empty = ground
  Eigen::MatrixXd frame{};    // R, m x k (m = element dimension); 3D contact rows t1, t2, n
  ElementPtr element{};
  // Travelling-wave systems only (hbm/travelling_wave.h): node B belongs to sector b_sector
  // (−1, 0 or +1; its DOFs dofs_b are its sector-0 copy's, in x, y, z triples when ≠ 0). 0
  // otherwise.
  int b_sector = 0;
};

struct Excitation {
  std::map<int, Eigen::VectorXcd> harmonics{};  // k ≥ 0 -> F_k (size ndof), N
};

enum class StaticCoupling { kUncoupled, kCoupled };

// How Newton solves dR/dx Δ = −R. Dense: LU of the n x n matrix. Structured: GMRES on
// (I + 𝔾 J_f) (products per harmonic with the complex nu x nu G_k and per pair with J_f),
// right-preconditioned by P = I + 𝔾 J_f,0, J_f,0 the element tangents at the zero-vibration state
// (stuck friction, closed preloaded contacts), i.e. per harmonic the complex LU of I + G_k K_0,
// factored once per Ω. Low rank: the structured solve with G_k never formed (issue 16 item 1):
// G_k z = Ψ (H_k (Ψᵀ z)) through the nm modes, and P⁻¹ by Woodbury over the modes,
//   (I + Ψ H_k Ψᵀ K_0)⁻¹ = I − Ψ H_k (I + S_0 H_k)⁻¹ Ψᵀ K_0,  S_0 = Ψᵀ K_0 Ψ (nm x nm, once),
// one complex LU of order nm per harmonic and Ω; the static problem's Newton steps by the same
// identity with its element tangents (exact). Memory O(nu·nm) instead of O(nu²): for a truncated
// modal model (nm < nu). Not with a travelling wave or rigid-body modes held by the elements
// (InvalidInput when asked for). Auto: structured when n >= kStructuredSolverThreshold, low rank
// among those when nm < nu and it applies.
enum class HbmLinearSolver { kAuto, kDense, kStructured, kLowRank };
inline constexpr int kStructuredSolverThreshold = 2000;
// Automatic static load steps with initial gaps: the touchdown cuts make the path exact for
// slip of fixed direction whatever the steps; the steps bound the error of backward Euler for slip
// whose direction turns (and of touchdowns beyond kMaxTouchdownCuts) and keep each Newton solve
// near its start.
inline constexpr int kStaticIncrements = 10;
// Touchdown cuts of a static loading path, at most (each costs one more static solve); touchdowns
// beyond them close within their step (backward Euler: their tangential motion in that step
// before touchdown counted as elastic).
inline constexpr int kMaxTouchdownCuts = 200;

struct HarmonicBalanceOptions {
  int harmonics = 1;                 // H: dynamic harmonics 1..H
  std::vector<int> harmonic_list{};  // if not empty, the dynamic harmonics (≥ 1, increasing),
                                     // e.g. {1, 3, 5}; overrides `harmonics`
  int time_samples = 64;             // N per period for AFT; N ≥ 2(2 H_max + 1)
  AftMethod aft = AftMethod::kEvent;  // aft.h: kEvent exact where it applies (falls back to
                                      // kSampled per cycle otherwise, flagged in the statistics)
  StaticCoupling static_coupling = StaticCoupling::kUncoupled;
  double residual_scale = 0.0;  // > 0: Newton's scale (m); 0: automatic (see residual_scale())
  NewtonOptions static_newton;  // for the static problem (each load step)
  // Load steps of the static problem (header comment, "Static loading path"): 0 automatic (1, or
  // kStaticIncrements when a friction element has an initial gap or interference), n ≥ 1: n equal
  // steps (1: one proportional step from the unloaded state), plus the touchdown cuts.
  int static_increments = 0;
  HbmLinearSolver linear_solver = HbmLinearSolver::kAuto;
  DampingMatrixMethod damping_matrix_method = DampingMatrixMethod::kStateSpace;
};
void validate(const HarmonicBalanceOptions& options);

// Memory a HarmonicBalanceSystem and its Newton solves take, in bytes, for contact_rows (nu) rows
// and the options' harmonics and samples (N): the AFT's sample derivatives ∂u/∂c for element
// dimensions 1..3 and a thread's workspace (≈ 184 N nc), the receptances G_k and, for the
// structured solve, their preconditioner LUs (2 · 16 nu² per harmonic), the dense path's 𝔾, dR/dx
// and its LU (3 · 8 n², n = nu nc), GMRES's Krylov basis. An estimate within a factor of about 2,
// to refuse an analysis that cannot fit before it starts.
double estimated_memory_bytes(int contact_rows, const HarmonicBalanceOptions& options);

class HarmonicBalanceSystem final : public ParametrizedSystem {
 public:
  // Validates everything (InvalidInput). Uncoupled: solves the static problem here
  // (static_summary() says whether it converged).
  HarmonicBalanceSystem(LinearModel model, std::vector<ContactPair> pairs, Excitation excitation,
                        HarmonicBalanceOptions options);
  // Sector 0 of a tuned cyclic structure under a travelling wave (hbm/travelling_wave.h): `model`
  // is the real diameter-0 model (harmonic 0 and the statics, as above), each dynamic harmonic k
  // takes wave.harmonics[k] (same rows as model.Phi) and B_k with the pairs' b_sector; G_k is
  // then complex and not symmetric. Only the diagonal modal damping (no modal_damping_matrix).
  // Everything below holds with G_k, u_lin,k of the wave; linear_model() and contact_modes() are
  // the diameter-0 model's.
  HarmonicBalanceSystem(LinearModel model, std::vector<ContactPair> pairs, Excitation excitation,
                        HarmonicBalanceOptions options, TravellingWave wave);

  int size() const override { return rows_ * nc_; }
  void evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& R, Eigen::MatrixXd* dR_dx,
                Eigen::VectorXd* dR_domega) const override;
  // Newton's convergence scale (m): ||R|| <= tolerance · residual_scale_at(Ω). options.
  // residual_scale if set, else the largest of three displacement scales of the contact rows:
  //   s_qs   = Σ_k ||B K⁺ F_k|| + ||u0||  the quasi-static linear response to every excitation
  //            harmonic (K⁺ = Φ diag(1/ω²) Φᵀ over the elastic modes) plus the static state;
  //   s_dyn  = ||u_lin(Ω)||               the dynamic linear response at Ω (its coefficients of
  //            the harmonics >= 1: the excitation through the receptance D_k(Ω)⁻¹);
  //   s_abs  = (Σ_k ||F_k|| + ||f0||) / (max_p ||K_p|| + 1/||G_0||)  an absolute floor: the force
  //            scale (excitation and static contact forces) over the stiffness scale (the
  //            largest element tangent K_p at the static state, plus the structure's at the
  //            contacts, G_0 = B K⁺ Bᵀ; Frobenius norms).
  // s_qs alone is 0 when the static load does not load the joints (a damper or a chain element
  // between two masses with the force on one of them): then the test compared round-off with
  // round-off and never converged. s_abs > 0 whenever there is a force; 1 if all three vanish
  // (no excitation, no preload: the solution is 0).
  // residual_scale() = max(s_qs, s_abs) (Ω-independent; arc-length's augmented equation).
  double residual_scale() const override { return residual_scale_; }
  double residual_scale_at(double omega) const override;
  // Structured solve (see HbmLinearSolver): GMRES to 1e-10 relative.
  bool has_structured_jacobian() const override { return structured_; }
  bool solve_jacobian(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& rhs,
                      Eigen::VectorXd& dx) const override;
  // GMRES products of the last structured solve (diagnostics).
  int last_gmres_iterations() const { return last_gmres_iterations_; }
  // Whether the low-rank structured solve is in use (HbmLinearSolver::kLowRank).
  bool low_rank() const { return low_rank_; }

  const HarmonicSet& unknown_harmonics() const { return aft_.basis().harmonics(); }
  // 0 followed by the dynamic harmonics: the harmonics every output carries.
  const std::vector<int>& output_harmonics() const { return output_harmonics_; }
  int contact_rows() const { return rows_; }                 // nu
  int pair_row(int pair) const { return pair_rows_[pair]; }  // r_p
  int master_dofs() const { return static_cast<int>(model_.Phi.rows()); }
  const std::vector<ContactPair>& pairs() const { return pairs_; }
  const Aft& aft() const { return aft_; }
  // The linear model the system was built with and its contact modes Ψ = BΦ (nu x nm).
  const LinearModel& linear_model() const { return model_; }
  const Eigen::MatrixXd& contact_modes() const { return Psi_; }
  // J = ∂F/∂x at unknowns x: the AFT's exact force Jacobian, block-diagonal per pair (n x n,
  // zero outside the blocks); dR/dx = I + 𝔾 J (with the static shift when rigid modes are held).
  // With `wider` (an AFT whose harmonics include the unknown ones): the same motion (x, its other
  // harmonics 0) and the Jacobian of the force harmonics of wider's basis with respect to the
  // motion's, in wider's layout (nu·nc' square).
  Eigen::MatrixXd force_jacobian(const Eigen::VectorXd& x, const Aft* wider = nullptr) const;
  const HarmonicBalanceOptions& options() const { return options_; }

  // With a modal damping matrix: whether the state-space expansion is used, and if it was asked
  // for but not used, why (empty otherwise).
  bool state_space_damping() const {
    return flexibility_->method() == ModalFlexibilityMethod::kStateSpace;
  }
  // The modal flexibility H_k(Ω) in use (modal_flexibility.h), chosen at construction.
  const ModalFlexibility& modal_flexibility() const { return *flexibility_; }
  const std::string& damping_matrix_note() const { return damping_matrix_note_; }

  const NewtonSummary& static_summary() const { return static_summary_; }
  // The static loading path taken: load steps solved (equal steps plus touchdown cuts; 1 for the
  // one proportional step) and the cuts among them.
  struct StaticPath {
    int steps = 1;
    int touchdown_cuts = 0;
  };
  const StaticPath& static_path() const { return static_path_; }
  // The constant the AFT adds to pair p's motion: (uncoupled) u0's segment minus (s, 0), s the
  // friction element's tangential anchor at the end of the static path (empty when both are 0,
  // coupled without an anchor). A tangent "at the static state" is the element's at this offset.
  const Eigen::VectorXd& pair_offset(int pair) const { return pair_offset_[pair]; }
  const Eigen::VectorXd& static_displacement() const { return u0_; }  // uncoupled u0 (nu)
  const Eigen::VectorXd& static_force() const { return f0_; }         // uncoupled f0 (nu)

  // Complex linear contact response u_lin,k(Ω) (nu) and the receptance G_k(Ω) (nu x nu).
  Eigen::VectorXcd linear_contact_response(int k, double omega) const;
  Eigen::MatrixXcd receptance(int k, double omega) const;

  // Guess for Newton: the linear response with every element replaced by its tangent at the
  // zero-vibration state (the static state when uncoupled): stuck friction, closed preloaded
  // contacts (`stuck` = true), or by no element at all (`stuck` = false: u = u_lin).
  Eigen::VectorXd linear_guess(double omega, bool stuck) const;

  // Element forces for unknowns x: F (nu·nc coefficients) and per pair its cycle statistics
  // and, if requested, the sampled cycle.
  void contact_forces(const Eigen::VectorXd& x, Eigen::VectorXd& forces,
                      std::vector<CycleStatistics>* stats,
                      std::vector<AftSamples>* samples = nullptr) const;
  // The sampled cycle (u, f over one period, local axes) of one pair at unknowns x.
  AftSamples pair_cycle(const Eigen::VectorXd& x, int pair) const;
  // Complex harmonics of a coefficient vector in the unknown layout: rows x output harmonics
  // (harmonic 0 from `static_part` when S has no 0; pass the uncoupled u0 or f0).
  Eigen::MatrixXcd to_complex(const Eigen::VectorXd& coefficients,
                              const Eigen::VectorXd& static_part) const;
  // Master-DOF harmonics, ndof x output harmonics, from the complex contact forces (nu x nh).
  // With held rigid-body modes (harmonic 0 shifted, see the header comment) the static column
  // also needs the static contact displacement: contact_displacement (nu x nh, the contact
  // displacements of the same point) or, when null, the uncoupled u0 (coupled statics: required).
  Eigen::MatrixXcd master_response(const Eigen::MatrixXcd& contact_force, double omega,
                                   const Eigen::MatrixXcd* contact_displacement = nullptr) const;
  // Whether harmonic 0 has rigid-body modes held by the elements (the shifted static problem).
  bool holds_rigid_modes() const { return static_shift_.size() > 0; }
  // The travelling wave the system was built with, or null.
  const TravellingWave* travelling_wave() const { return wave_ ? &*wave_ : nullptr; }

 private:
  // G_k(Ω) per unknown harmonic (complex nu x nu; 𝔾 is their real split), u_lin(Ω) (n) and,
  // if requested, du_lin/dΩ and H_k(Ω) with its derivative products; when structured, the
  // preconditioner's LUs. The last one is cached: Newton iterations at one Ω and the recovery
  // reuse it.
  struct CondensedOperator {
    double omega = 0.0;
    bool has_derivative = false;
    std::vector<Eigen::MatrixXcd> G;  // per harmonic position
    // H_k(Ω) per position (null for harmonic 0 with held rigid-body modes: the shifted G̃_0).
    std::vector<std::unique_ptr<const ModalFlexibility::Harmonic>> H;
    std::vector<ComplexDenseLu> precondition;  // I + G_k K_0 (LAPACK's zgetrf)
    // Low rank (G empty): H_k as nm x nm and the LU of the capacitance I + S_0 H_k per position.
    std::vector<Eigen::MatrixXcd> Hm;
    std::vector<Eigen::PartialPivLU<Eigen::MatrixXcd>> capacitance;
    Eigen::VectorXd ulin, dulin;
    Eigen::MatrixXd Gdense;  // 𝔾 (n x n, real split), dense solver path only
  };
  // 𝔾 v and (∂𝔾/∂Ω) v in the unknown layout.
  Eigen::VectorXd apply_G(const CondensedOperator& op, const Eigen::VectorXd& v) const;
  Eigen::VectorXd apply_dG(const CondensedOperator& op, const Eigen::VectorXd& v) const;
  Eigen::MatrixXd dense_G(const CondensedOperator& op) const;
  Eigen::VectorXd apply_preconditioner(const CondensedOperator& op, const Eigen::VectorXd& v) const;
  // Low rank: the unknown layout as real columns (re, −im of each harmonic position; nu x 2·np)
  // and back, and the two products above through the modes.
  Eigen::MatrixXd harmonic_columns(const Eigen::VectorXd& v) const;
  void scatter_columns(const Eigen::MatrixXd& columns, Eigen::VectorXd& out) const;
  Eigen::VectorXd apply_G_low_rank(const CondensedOperator& op, const Eigen::VectorXd& v) const;
  Eigen::VectorXd apply_preconditioner_low_rank(const CondensedOperator& op,
                                                const Eigen::VectorXd& v) const;
  // ||G_0||_F (Frobenius), without forming G_0 when low rank.
  double static_receptance_norm() const;
  void build_stuck_tangent();
  struct OperatorCache {
    std::mutex mutex;
    std::shared_ptr<const CondensedOperator> last;
  };
  std::shared_ptr<const CondensedOperator> condensed_operator(double omega, bool derivative) const;
  // H_k(Ω) rhs for a complex nm x c rhs (harmonic 0 with held rigid-body modes: H̃_0).
  Eigen::MatrixXcd modal_flexibility_times(int k, double omega, const Eigen::MatrixXcd& rhs) const;

  void solve_static();
  double displacement_floor() const;  // s_abs (see residual_scale_at)
  void build_static_flexibility();
  // out_0 −= G̃_0 K_s v_0 on the harmonic-0 coefficients (nothing without the shift), and the
  // same on the harmonic-0 block of a dense Jacobian.
  void subtract_static_shift(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
  void subtract_static_shift(Eigen::MatrixXd& J) const;

  LinearModel model_;
  std::vector<ContactPair> pairs_;
  Excitation excitation_;
  HarmonicBalanceOptions options_;
  Aft aft_;
  int nc_ = 0;
  int rows_ = 0;
  std::vector<int> pair_rows_;
  std::vector<int> output_harmonics_;
  Eigen::MatrixXd Psi_;                         // B Φ, nu x nm
  std::map<int, Eigen::VectorXcd> modal_load_;  // k -> Φᵀ F_k
  Eigen::VectorXd
      static_modes_;  // 1 for elastic modes (elastic_modes: ω_r² > kRigidModeRatio max ω²)
  // Held rigid-body modes (build_static_flexibility), else all empty: H̃_0 (nm x nm), K_s per
  // contact row (N/m), G̃_0 = Ψ H̃_0 Ψᵀ and G̃_0 K_s (nu x nu).
  Eigen::MatrixXd static_flexibility_;
  Eigen::VectorXd static_shift_;
  Eigen::MatrixXd static_G_, static_shift_G_;
  Eigen::VectorXd u0_, f0_;
  Eigen::VectorXd static_anchor_;  // per contact row: the anchor s (tangential rows), else 0
  NewtonSummary static_summary_;
  StaticPath static_path_;
  double residual_scale_ = 1.0;
  bool structured_ = false;
  bool low_rank_ = false;
  // Per harmonic position, per pair: K_0's m x m block (K_0 is block-diagonal per pair).
  std::vector<std::vector<Eigen::MatrixXd>> stuck_tangent_;
  std::vector<Eigen::MatrixXd> stuck_gram_;  // low rank, per position: S_0 = Ψᵀ K_0 Ψ (nm x nm)
  mutable int last_gmres_iterations_ = 0;
  std::shared_ptr<OperatorCache> cache_ = std::make_shared<OperatorCache>();
  // Element forces and cycle statistics of the last evaluate(), for contact_forces at the same x.
  struct ForceCache {
    std::mutex mutex;
    Eigen::VectorXd x, forces;
    std::vector<CycleStatistics> stats;
  };
  std::shared_ptr<ForceCache> force_cache_ = std::make_shared<ForceCache>();
  // Per contact pair, where its last cycle started (aft.h, AftWarmStart; read by kEventPlanar):
  // only where the next cycle starts, never the answer beyond the AFT's closure tolerance.
  struct WarmStarts {
    std::mutex mutex;
    std::vector<AftWarmStart> pairs;
  };
  std::shared_ptr<WarmStarts> warm_starts_ = std::make_shared<WarmStarts>();
  // The AFT marches a friction pair's motion minus its anchor (pair_offset): its samples' u get
  // the anchor back, so they are the pair's relative displacement.
  void restore_anchor(size_t p, AftSamples* samples) const;
  // aft_.evaluate of pair p's coefficients c with its warm start.
  CycleStatistics evaluate_pair(size_t p, const Eigen::VectorXd& c, const Eigen::VectorXd& offset,
                                Eigen::VectorXd& f, Eigen::MatrixXd* J,
                                AftSamples* samples = nullptr) const;
  // master_response's harmonic-0 column for the last contact force it was asked with (the frozen
  // static force of the uncoupled formulation: the same at every point of a sweep).
  struct StaticResponseCache {
    std::mutex mutex;
    Eigen::VectorXcd force, response;
  };
  std::shared_ptr<StaticResponseCache> static_response_cache_ =
      std::make_shared<StaticResponseCache>();
  std::vector<Eigen::VectorXd> pair_offset_;  // per pair: see pair_offset()
  std::unique_ptr<const ModalFlexibility> flexibility_;  // H_k(Ω), chosen at construction
  std::string damping_matrix_note_;
  std::optional<TravellingWave> wave_;
  const TravellingWaveFlexibility* wave_flexibility_ = nullptr;  // flexibility_ when wave_
  HarmonicBalanceSystem(LinearModel model, std::vector<ContactPair> pairs, Excitation excitation,
                        HarmonicBalanceOptions options, std::optional<TravellingWave> wave);
};

}  // namespace stickslip
