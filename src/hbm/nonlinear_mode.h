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
// Its modal amplitude is the fundamental's projection z = ηᵀ Q_1 (Q_1 = −H_1 Ψᵀ F_1, the complex
// modal coordinates of harmonic 1; z = φᵀ M X_1 on the master DOFs), in √kg·m. Two more
// equations close the system (unknowns: the contact harmonics, Ω in rad/s, ξ in 1/s):
//   amplitude  s (Re z − a) = 0,   phase  s Im z = 0   (the mode's coordinate is a cos Ωt + …),
// scaled by s = ||Ψ η|| (the contact motion per unit modal amplitude; ||Φ η|| if the mode does not
// move the contacts) so that every row is in metres.
//
// Limitation of the condensed form: the mode's force must pass through the elements. A mode of the
// structure without its elements (ω̃ = some ω_r, the elements' tangent 0 in the mode, e.g. a cubic
// spring without linear part) makes G_1 singular at the solution; friction contacts (stuck
// tangent kt > 0) approach the sliding structure's frequency only as a → ∞.
//
// The branch is continued in λ = ln a over the requested amplitudes (a stepped sweep with a secant
// predictor and step halving, continuation/sweep.h), starting from the linear mode at the first
// (smallest) amplitude: U_1 = a Ψ η, Ω = ω̃, ξ = ηᵀ C_m η. Newton's scale at amplitude a is
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
  // Complex modal coordinate z = ηᵀ Q_1 of the followed mode at y.
  std::complex<double> modal_amplitude(const Eigen::VectorXd& y) const;
  // Master-DOF harmonics (ndof x output harmonics) at y: harmonic 0 from the system's static
  // balance, harmonics ≥ 1 X_k = Φ H_k(Ω, ξ) (−Ψᵀ F_k).
  Eigen::MatrixXcd master_response(const Eigen::VectorXd& y) const;
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
  Eigen::VectorXd unknowns;        // y = [U; Ω; ξ]
  Eigen::MatrixXcd master;         // ndof x nh master-DOF harmonics
  double dissipated_energy = 0.0;  // per cycle, summed over the pairs, J
};

struct NonlinearModeResult {
  int mode = 1;
  double linear_omega = 0.0;               // ω̃ of the stuck mode, rad/s
  double linear_xi = 0.0;                  // its ξ at the linear limit, 1/s
  std::vector<int> harmonics;              // output harmonics (columns of master)
  std::vector<NonlinearModePoint> points;  // one per requested amplitude, in order
  bool completed = false;                  // every point converged
  std::string message;
};

// Throws InvalidInput on bad options (mode out of range, amplitudes), or when the system's
// harmonics do not include 1, or has held rigid-body modes with static: coupled.
NonlinearModeResult nonlinear_mode(const HarmonicBalanceSystem& system,
                                   const NonlinearModeOptions& options);

}  // namespace stickslip
