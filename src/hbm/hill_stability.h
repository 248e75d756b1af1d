// Stability of a periodic solution of the condensed harmonic balance by Hill's method
// (docs/conventions.md, "Stability").
//
// The structure's modal equations (harmonic_balance.h) q̈ + C_m q̇ + diag(ω²) q = Φᵀ F(t) − Ψᵀ f(u),
// u = Ψ q, linearised about the periodic solution, are solved for perturbations of Floquet form
//   δq(t) = e^{μt} p(t),  p T-periodic (T = 2π/Ω), expanded in the harmonics S = 0..H_max,
// with the element forces' perturbation δF = J δU, J = ∂F/∂U the AFT's exact Jacobian of the
// force coefficients at the solution (block-diagonal per pair: the Jacobian Newton already has
// when the solution's harmonics are 0..H_max; otherwise — static: uncoupled has no harmonic 0, a
// harmonic list may have gaps — the same motion's Jacobian from an AFT over 0..H_max). Harmonic 0
// is needed: the perturbation of a mode at ω_r is e^{iω_r t} times a p(t) centred on harmonic 0
// with side bands at ±Ω, ±2Ω... from the time-varying contact stiffness; without it every mode is
// represented off-centre, and the exponents of modes far from Ω came out wrong (measured on the
// reference joint: growth rates of 10²–10⁴ 1/s, all spurious).
// With d/dt → μ + Ω D (D the coefficients' derivative, fourier.h) this is the quadratic
// eigenvalue problem
//   [μ² I + μ (2Ω D + C_m) + (Ω² D² + Ω C_m D + diag(ω²) + Ψ_Sᵀ J_eff Ψ_S)] p = 0
// over the modes' coefficients (Ψ_S = Ψ ⊗ I_nc), solved through its companion linearisation
// (real, 2·n_d·nc), scaled to unit size (μ = γλ, γ² = ‖M0‖∞), by LAPACK's dgeev (balanced).
//
// Modes. The modes with ω_r ≤ dynamic_mode_factor · (H_max + 1) · Ω are dynamic (all of them when
// the factor is 0); the others respond quasi-statically to the perturbation: their flexibility
// G_s = Ψ_s diag(1/ω_s²) Ψ_sᵀ (undamped, μ-independent) is folded into the elements,
//   J_eff = (I + J G_s)⁻¹ J,
// and their own exponents (≈ −c_r/2 ± iω_r, stable) are not computed. Exact in the limit of the
// factor → ∞; the error is O((Ω H_max/ω_s)²) of the coupling through those modes.
//
// Selection. Each Floquet exponent μ appears in the Hill spectrum as the family μ + i m Ω, the
// member m having its eigenvector's periodic part p(t) shifted by e^{−imΩt} (for a time-invariant
// system exactly: p concentrated on the complex harmonic −m). The physical representative is the
// member whose p is centred on harmonic 0: per eigenvalue the mean complex harmonic index
// k̄ = Σ k |p_k|² / Σ |p_k|² (over k = ±S, p_k the coefficient of e^{ikΩt}: Parseval's weights)
// is computed. Members of one family differ in k̄ by whole numbers, so exactly one has |k̄| ≤ ½
// (two, ±½, for a real negative multiplier); only such centred members (|k̄| ≤ 0.55, the margin
// for the truncation's distortion) are candidates. A cluster of equal eigenvalues (to 1e-8 of
// the scaled companion matrix's norm: two families that meet, μ_s = μ_r + imΩ, exactly so in a
// time-invariant system with equal damping) has an invariant subspace, not eigenvectors: the
// solver may return mixtures of one family's centred member and the other's outer one; within
// the cluster the basis that diagonalises the harmonic index gives each member its index back.
// The 2 n_d candidates with the smallest |k̄| are taken (ties within 0.25: the smaller |Im μ|),
// one member per family: a candidate whose multiplier e^{μT} equals one already taken (to 1e-6)
// while its Im μ differs from it by Ω/2 or more is another member of that family and is passed
// over, and taken only if the candidates run out (two families with one multiplier). This
// matters for real negative multipliers (period doubling): their family σ + i(m + ½)Ω has two
// members equally centred, σ ± iΩ/2, and taking both would leave another family out — a real
// negative pair −e^{σ1 T}, −e^{σ2 T} must give σ1 and σ2. The imaginary-part criterion alone (the
// 2 n_d smallest |Im μ|) fails when a mode lies above H Ω: its family's members within the strip
// are cut off by the truncation and another mode's outer members take their place. The real
// part — all stability needs — is common to a family; the centred member's imaginary part is
// near the mode's own frequency (not folded into the strip).
// A family without a centred member is not placed (FloquetSummary::unplaced_exponents): its
// members are the truncation's (outer members of modes far above HΩ whose side bands H cuts off,
// with real parts of either sign — +300 1/s on the reference joint with 52 dynamic modes); filling
// the count with them made stable points unstable. The multiplier of largest modulus is
// ρ = exp(max Re μ · T) over the placed exponents; the solution is stable when max Re μ ≤
// stability_tolerance · Ω.
//
// Non-smooth laws. J is the derivative of the converged periodic force cycle with respect to the
// periodic motion (hysteresis: the stick phases' memory is in it). For friction this is the
// Jacobian of the periodic map restricted to periodic perturbations, frozen over the
// perturbation's slow e^{μt} envelope: exact for smooth memoryless laws (cubic spring, and the
// sampled law in its stuck or open phases), an approximation across stick–slip transitions, where
// the law is not differentiable; the exponents are then those of the harmonic-balance model as
// solved (docs/conventions.md gives the tests that bound it).
//
// Uncoupled statics: the static state is frozen in the solution (u0 the offset of the cycle); the
// perturbation's harmonic 0 moves the mean about it.
#pragma once

#include <complex>
#include <vector>

#include <Eigen/Core>

#include "hbm/harmonic_balance.h"

namespace stickslip {

struct HillOptions {
  double dynamic_mode_factor = 4.0;   // ≥ 0; 0: every mode dynamic
  double stability_tolerance = 1e-7;  // > 0: stable when max Re μ ≤ tolerance · Ω
};
void validate(const HillOptions& options);

struct FloquetSummary {
  // The selected μ (1/s), by decreasing real part: 2 n_d − unplaced_exponents of them.
  Eigen::VectorXcd exponents{};
  double max_real_part = 0.0;   // 1/s, over `exponents` (NaN when none was placed)
  double max_multiplier = 1.0;  // |ρ| = exp(max_real_part · 2π/Ω)
  bool stable = true;           // max_real_part ≤ stability_tolerance · Ω (false when NaN)
  // Exponents whose family has no centred member in the truncated Hill spectrum (see
  // "Selection"): not placed, so their real parts are unknown; stable and max_multiplier are
  // those of the placed ones.
  int unplaced_exponents = 0;
  int dynamic_modes = 0;
  int quasi_static_modes = 0;
};

// Floquet exponents of the solution x at Ω (x: the converged unknowns of `system`). Throws
// InvalidInput on bad options, Ω ≤ 0 or a wrong size of x.
FloquetSummary hill_stability(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                              double omega, const HillOptions& options = {});

// Where the multiplier ρ = e^{μT} (T = 2π/Ω) of an exponent μ lies by its angle θ = Im μ · T
// (mod 2π): on the positive real axis (|θ| ≤ kRealMultiplierAngle: a fold or a branch point when
// it leaves the unit circle), on the negative one (|θ| ≥ π − kRealMultiplierAngle: period
// doubling) or off the real axis (a complex pair: Neimark–Sacker). Real multipliers give exactly
// θ = 0 (a real eigenvalue of the real companion matrix) or θ = π up to the truncation of the
// harmonics (a family μ + i(m + ½)Ω cut at ±H).
enum class MultiplierKind { kPlusOne, kMinusOne, kComplex };
// 0.02 rad (1.1°): a complex pair closer than that to the real axis counts as real there.
inline constexpr double kRealMultiplierAngle = 0.02;
MultiplierKind multiplier_kind(std::complex<double> exponent, double omega);

// The largest Re μ over the exponents of one kind (−∞ when there is none), 1/s.
double largest_real_part(const FloquetSummary& summary, MultiplierKind kind, double omega);
// The multiplier e^{μT} of that exponent (NaN when there is none).
std::complex<double> critical_multiplier(const FloquetSummary& summary, MultiplierKind kind,
                                         double omega);

// The kinds of multipliers that crossed the unit circle between two solutions a (at Ω_a) and b
// (at Ω_b) of a curve: those whose number of exponents with Re μ > stability_tolerance · Ω
// differs between a and b, in the order kPlusOne, kMinusOne, kComplex.
std::vector<MultiplierKind> unit_circle_crossings(const FloquetSummary& a, double omega_a,
                                                  const FloquetSummary& b, double omega_b,
                                                  const HillOptions& options = {});

}  // namespace stickslip
