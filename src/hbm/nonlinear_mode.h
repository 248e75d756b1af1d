// Nonlinear modes of the condensed harmonic balance by the extended periodic motion concept (EPMC,
// Krack 2015; docs/conventions.md, "Nonlinear modes").
//
// The autonomous structure with a negative mass-proportional damping term −ξ M,
//   M ẍ + (C − ξ M) ẋ + K x + Bᵀ f(B x) = F_0,
// has, for the right ξ, periodic solutions of frequency Ω: the nonlinear mode. ξ balances the
// energy the damping and the elements take out per cycle; the modal damping ratio is D = ξ/(2Ω).
// In the condensed form of harmonic_balance.h (mass-normalised modes, so −ξM becomes −ξ I on the
// modal coordinates) the harmonics k ≥ 1 of the contact displacements satisfy, without excitation,
//   U_k + G_k(Ω, ξ) F_k(U) = 0,  G_k = Ψ H_k Ψᵀ,
//   H_k(Ω, ξ) = (diag(ω_r²) − (kΩ)² I + i kΩ (C_m − ξ I))⁻¹   (C_m = diag(c_r) or the matrix),
// split into real rows as in harmonic_balance.h; harmonic 0 (static: coupled) keeps the system's
// static balance (static loads included), static: uncoupled keeps its frozen static state.
// Excitation of harmonics ≥ 1 in the system is ignored.
//
// The mode followed: the linear mode `mode` (1-based, ascending frequency) of the stuck assembly,
// the structure with every element replaced by its tangent at the static state (stuck friction,
// closed preloaded contacts; the assembly `stickslip modes` lists when every contact is closed
// there): K_stuck η = ω̃² η in modal coordinates, K_stuck = diag(ω_r²) + Ψᵀ K_t Ψ, ηᵀη = 1 (so the
// master-DOF shape φ = Φ η is mass-normalised), its largest component positive.
// Its modal amplitude is the mass norm of the fundamental, q = ||Q_1|| (Q_1 = −H_1 Ψᵀ F_1, the
// complex modal coordinates of harmonic 1; q² = X_1ᴴ M X_1 on the master DOFs), in √kg·m, and its
// phase that of the projection on the stuck mode, z = ηᵀ Q_1 = φᵀ M X_1. Two more equations close
// the system (unknowns: the contact harmonics, Ω in rad/s, ξ in 1/s):
//   amplitude  s (q − a) = 0,   phase  s Im z = 0,
// scaled by s = ||Ψ η|| (the contact motion per unit modal amplitude; ||Φ η|| if the mode does not
// move the contacts) so that every row is in metres. The norm, not the projection z, measures the
// amplitude because the shape can leave the stuck mode: on the reference joint, when every pair
// slips, mode 4's motion grows eightfold per unit of z (the beams' ends slide apart) and z is no
// longer monotonic along the branch, where q is (Krack 2015 normalises the same way).
//
// Limitation of the condensed form: the mode's force must pass through the elements. A mode of the
// structure without its elements (ω̃ = some ω_r, the elements' tangent 0 in the mode, e.g. a cubic
// spring without linear part) makes G_1 singular at the solution; friction contacts (stuck
// tangent kt > 0) approach the sliding structure's frequency only as a → ∞.
//
// The branch is continued in λ = ln a over the requested amplitudes (a stepped sweep with a secant
// predictor, step halving and an arc-length fallback, continuation/sweep.h), starting from the
// linear mode at the first (smallest) amplitude: U_1 = a Ψ η, Ω = ω̃, ξ = ηᵀ C_m η. The sweep works
// in dimensionless unknowns (U_k/(a s), U_0 over the static scale, Ω/ω̃, ξ/ω̃): in y the columns of
// Ω and ξ are 1e-10 of the others and the arc-length fallback, needed where the branch folds in
// amplitude (the joint's passage to gross slip), could not start. Newton's scale at amplitude a is
// a · s (plus the system's static scale with static: coupled).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "continuation/newton.h"
#include "continuation/parametrized_system.h"
#include "continuation/sweep.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {

struct NonlinearModeOptions {
  int mode = 1;                    // 1-based mode of the stuck assembly, ≤ the number of modes
  std::vector<double> amplitudes;  // modal amplitudes a (√kg·m): finite, > 0, strictly increasing
  NewtonOptions newton;
  int max_step_halvings = 4;    // per amplitude (SteppedSweepOptions.max_step_halvings)
  ProgressCallback on_point{};  // after each amplitude point (λ = ln a)
};
// Throws InvalidInput naming the field and the rule it broke.
void validate(const NonlinearModeOptions& options);

// The stuck assembly's linear modes in the system's modal coordinates (see the header comment):
// ω̃² ascending (rad²/s²) and η (nm x nm, columns, ηᵀη = I, largest component of each positive).
struct StuckModes {
  Eigen::VectorXd omega2;
  Eigen::MatrixXd eta;
};
StuckModes stuck_modes(const HarmonicBalanceSystem& system);

// Where the followed mode's nonlinear range starts, estimated from the linear stuck mode η: the
// smallest modal amplitude a at which some friction pair (FrictionContact3D, Jenkins1D) reaches
// its Coulomb limit or opens. Each pair's force along the mode is f(c) = f_s + c K_p u_p
// (c = a cos Ωt ∈ [−a, a]; f_s its static force, K_p its tangent at the static state, u_p = (Ψη)_p
// its relative motion per unit modal amplitude): 3D contact, the smallest |c| with
// |τ_s + c τ_1| = μ (N_s + c N_1) or N_s + c N_1 = 0; Jenkins, |τ_s + c τ_1| = μN. Exact for the
// first slip of the one-harmonic mode growing from rest (a real mode shape moves the forces along
// lines); +∞ when no friction pair moves in the mode, 0 when one is open at rest. Where the normal
// load varies along the mode (N_1 ≠ 0) a periodic cycle can stick above it with a tangential
// offset the slip left (shakedown, up to a |τ_1| = μN_s): the EPMC, which computes periodic cycles,
// may then find the pair stuck there.
double first_slip_amplitude(const HarmonicBalanceSystem& system, const Eigen::VectorXd& eta);

// The extended system R(y, λ) with y = [U; Ω; ξ] (size system.size() + 2) and λ = ln a.
class NonlinearModeSystem final : public ParametrizedSystem {
 public:
  // eta: the followed mode in modal coordinates (nm), ηᵀη = 1. The system must outlive this.
  NonlinearModeSystem(const HarmonicBalanceSystem& system, Eigen::VectorXd eta);
  int size() const override { return n_ + 2; }
  void evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd& R, Eigen::MatrixXd* dR_dy,
                Eigen::VectorXd* dR_dlambda) const override;
  double residual_scale() const override { return residual_scale_at(0.0); }
  double residual_scale_at(double lambda) const override;

  // The linear mode at amplitude a (the first guess).
  Eigen::VectorXd linear_guess(double amplitude) const;
  // The modal amplitude q = ||Q_1|| at y.
  double modal_amplitude(const Eigen::VectorXd& y) const;
  // Master-DOF harmonics (ndof x output harmonics) at y: harmonic 0 from the system's static
  // balance, harmonics ≥ 1 X_k = Φ H_k(Ω, ξ) (−Ψᵀ F_k). modal_norm (may be null): ||Q_1||₂,
  // Q_1 the modal coordinates of harmonic 1 (X_1 = Φ Q_1).
  Eigen::MatrixXcd master_response(const Eigen::VectorXd& y, double* modal_norm = nullptr) const;
  double linear_omega() const { return omega_lin_; }  // ω̃, rad/s
  double linear_xi() const { return xi_lin_; }        // ηᵀ C_m η, 1/s
  double scale() const { return s_; }                 // s (m per √kg·m)

 private:
  // H_k(Ω, ξ) rhs and its derivatives in Ω and ξ applied to rhs (nm x c complex).
  void flexibility(int k, double omega, double xi, const Eigen::MatrixXcd& rhs,
                   Eigen::MatrixXcd* H_rhs, Eigen::MatrixXcd* dH_domega_rhs,
                   Eigen::MatrixXcd* dH_dxi_rhs) const;
  void forces(const Eigen::VectorXd& x, Eigen::VectorXd& F, Eigen::MatrixXd* J) const;

  const HarmonicBalanceSystem& system_;
  Eigen::VectorXd eta_;
  int n_ = 0, rows_ = 0, nc_ = 0, nm_ = 0;
  double s_ = 1.0, omega_lin_ = 0.0, xi_lin_ = 0.0;
  bool dense_damping_ = false;
};

struct NonlinearModePoint {
  double amplitude = 0.0;      // modal amplitude a, √kg·m
  double omega = 0.0;          // rad/s
  double xi = 0.0;             // 1/s
  double damping_ratio = 0.0;  // D = ξ / (2Ω)
  bool converged = false;
  int iterations = 0;
  double residual_norm = 0.0;   // ||R||₂ (m)
  double residual_scale = 1.0;  // Newton's scale at a (m)
  std::string message;
  Eigen::VectorXd unknowns;  // y = [U; Ω; ξ]
  Eigen::MatrixXcd master;   // ndof x nh master-DOF harmonics
  // q = ||Q_1||₂ (√kg·m): the amplitude of the fundamental X_1 = Φ Q_1 in the mass norm,
  // q² = X_1ᴴ M X_1 (a, the projection on the stuck mode, is ≤ q; equal for a linear mode).
  double modal_norm = 0.0;
  double dissipated_energy = 0.0;  // per cycle, summed over the pairs, J
  // The contact state over the cycle (converged points): the share of the pairs that slip, and
  // that separate, over part of the cycle, and the mean over the pairs of the cycle's fraction in
  // slip (CycleStatistics).
  double pairs_slipping = 0.0;
  double pairs_separating = 0.0;
  double mean_slip_fraction = 0.0;
};

struct NonlinearModeResult {
  int mode = 1;
  double linear_omega = 0.0;          // ω̃ of the stuck mode, rad/s
  double linear_xi = 0.0;             // its ξ at the linear limit, 1/s
  double first_slip_amplitude = 0.0;  // first_slip_amplitude(system, η), √kg·m (may be ∞)
  std::vector<int> harmonics;         // output harmonics (columns of master)
  std::vector<NonlinearModePoint> points;  // one per requested amplitude, in order
  bool completed = false;                  // every point converged
  std::string message;
};

// The forced response predicted from a nonlinear mode (single nonlinear mode theory, SNMT:
// Szemplińska-Stupnicka 1979, Krack et al. 2013/2015). The response to the harmonic-1 excitation
// F̂ (x_F(t) = Re(F̂ e^{iΩt}), master DOFs, N) is taken as the nonlinear mode at some amplitude,
// shifted in time, x(t) ≈ Σ_k Re(X_k(a) e^{ikθ} e^{ikΩt}), and projected on the mode's
// fundamental ψ = X_1/q (ψᴴMψ = 1, q = modal_norm):
//   (ω(a)² − Ω² + i ξ(a) Ω) q e^{iθ} = ψᴴ F̂        (ξ = 2 D ω: the mode's damping, 1/s).
// Its modulus gives, per amplitude, (ω² − Ω²)² + ξ²Ω² = P², P = |ψᴴF̂|/q, a quadratic in Ω²:
//   Ω² = ω² − ξ²/2 ± √(P² − ξ²ω² + ξ⁴/4),
// so two excitation frequencies (below and above ω(a)), one (the lower root Ω² ≤ 0), or none (the
// amplitude is above the forced peak, or ψᴴF̂ = 0). The mode's damping ξ(a) is the energy balance
// of the free mode at its own frequency ω(a): a friction loss, independent of the frequency in
// the forced response, enters here as ξΩ, so the prediction is exact (for one mode, one
// harmonic) where Ω = ω(a), at the backbone, and off by the factor Ω/ω in that loss elsewhere.
struct ForcedResponsePrediction {
  int point = 0;            // the mode's point (NonlinearModeResult.points)
  bool above = false;       // the root Ω above ω(a) (else below)
  double omega = 0.0;       // excitation frequency Ω, rad/s
  double phase = 0.0;       // θ, rad: the response is the mode shifted by θ/Ω in time
  Eigen::MatrixXcd master;  // ndof x nh: X_k(a) e^{ikθ}, the predicted master-DOF harmonics
};
// One prediction per root along the response curve: the roots below ω(a) by increasing
// amplitude, then those above by decreasing amplitude (the curve over the peak); converged mode
// points only. force: F̂ on the master DOFs (size ndof). Needs harmonic 1 in mode.harmonics.
std::vector<ForcedResponsePrediction> predict_forced_response(const NonlinearModeResult& mode,
                                                              const Eigen::VectorXcd& force);

// Throws InvalidInput on bad options (mode out of range, amplitudes), or when the system's
// harmonics do not include 1, or has held rigid-body modes with static: coupled.
NonlinearModeResult nonlinear_mode(const HarmonicBalanceSystem& system,
                                   const NonlinearModeOptions& options);

}  // namespace stickslip
