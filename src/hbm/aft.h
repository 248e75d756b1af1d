// Alternating frequency–time (AFT) evaluation of one nonlinear element.
//
// Input: the harmonic coefficients c (m·nc, signal-major in the layout of fourier.h: component d,
// coefficient i at d·nc + i) of the element's local relative displacement, plus an optional
// constant offset u0 (m; the frozen static displacement of the `uncoupled` formulation, added to
// every sample). Then
//   u(t_j) = u0 + E c_d   (N samples),  f = element.march(u)   (converged hysteresis cycle),
//   F = P f               (force coefficients, same layout as c),
// and on request the EXACT Jacobian ∂F/∂c (m·nc x m·nc) = P ∂f/∂c, with ∂f/∂c propagated by the
// element through its time march (stick, slip, lift-off, the period wrap).
// Only harmonics in the basis's set are returned; aliasing of higher ones is the usual AFT error,
// controlled by N.
//
// Three methods (AftMethod):
//  - kSampled: the above. The piecewise law sampled at N instants: every transition (stick/slip,
//    lift-off) costs accuracy, O(N^-1.4..-2) in the force coefficients.
//  - kEvent: exact for Jenkins1D and FrictionContact3D (lift-off included). Collinear tangential
//    motion (the harmonic coefficient vectors of (u_t1, u_t2) parallel to one direction e; the
//    normal free): the switching functions of the law (μN ∓ τ in stick, the slip rate
//    kt u_e' − μN' in slip, N at lift-off and touchdown) are trigonometric polynomials between
//    transitions; each transition is bracketed on the N-point grid (plus an interior-minimum check
//    per interval) and located to round-off by safeguarded Newton; the force's Fourier integrals
//    are Gauss–Legendre sums per smooth segment, with enough nodes for the segment's trigonometric
//    degree that they are exact to round-off (0.75 H_max L + 10 nodes on a segment of length L).
//    Tangential motion that is not collinear, and a stuck cycle holding a tangential force off e:
//    the sampled method (fallback, below). ∂F_⊥/∂c_⊥ of a collinear cycle: the sampled method's.
//  - kEventPlanar: kEvent, and general planar motion (event_aft_planar.cpp; opt-in because on the
//    reference sweep it costs 9–18 times the sampled AFT at N = 64, though half the time of N =
//    4096, which is still 1e-6 off: docs/performance.md). In slip τ = μN e(φ) and the direction
//    obeys φ' = kt e⊥·u_t'/(μN) (from τ' = kt (u_t' − λe), |τ| = μN; slip rate λ = e·u_t' −
//    μN'/kt), integrated by 8-stage Gauss collocation (order 16, A-stable) with error control; slip
//    → stick (λ = 0) is located on the integrated solution by Newton on the last step's length;
//    stick → slip ((μN)² − |τ|² = 0, degree 2 H_max) and lift-off/touchdown are bracketed on a grid
//    refined to π/(4 H_max). The periodic cycle: from the virgin state two periods, then Newton on
//    the slip angle at a point mid-way in a slip segment (a cycle with an open segment closes at
//    once: touchdown forgets the history). With an AftWarmStart from the element's previous call,
//    the march starts where that cycle started (Newton on the angle from its angle; with the same
//    arguments, the final period at once), the virgin march only when that start does not apply.
//    The cycle is the periodic one of the continuous law (the sampled law's limit N → ∞). N sets
//    only the bracketing grid, the largest step, and the samples returned in AftSamples. Jacobian:
//    the force is continuous at every transition, so the boundary terms of the Leibniz rule cancel.
//    Event-time terms: slip → stick: none (the anchor μN e − kt u_t has derivative −kt λ e = 0
//    there); stick → slip: none (the stick force's angle turns at kt e⊥·u_t'/|τ|, the slip ODE's
//    rate); touchdown → stick (τ_a = 0): ∂θ_a = −∂N(θ_a)/N'(θ_a), included; touchdown → slip along
//    u_t': the start angle's change plus −φ'(θ_a+) ∂θ_a with the regular solution's start rate
//    φ'(θ_a+) = kt e⊥·u_t''/(μN' + kt|u_t'|), included (the FD tests fail without either). In slip
//    the variational equations of φ are integrated by the same collocation steps (the derivative of
//    the discrete map), and the periodicity of the start angle adds ∂F/∂φ_s (1 − ∂P/∂φ_s)⁻¹ ∂P/∂c.
//    Lift-off: as N → 0 the ODE is singular (φ' ∝ 1/N; φ tends to the direction of u_t' like (θ_l −
//    θ)^α, α = kt|u_t'|/(μ|N'|), and ∂φ/∂c grows like (θ_l − θ)^(α−1), unbounded for α < 1); the
//    force's sensitivity μN e⊥ ∂φ stays bounded and integrable and vanishes at θ_l, where the force
//    itself is 0 (no boundary term). The steps shrink geometrically towards θ_l, with the error
//    weighted by N/N_scale; after lift-off the state is history-free, so nothing propagates past
//    it. Fallback to the sampled method, with CycleStatistics::aft_fallback set so callers can say
//    so: any other element; a cycle that cannot be closed (Newton on the slip angle, or a step that
//    cannot be solved). A 3D cycle stuck throughout after slipping in its transient is one of a
//    family of stuck cycles: the law's history from the virgin state at θ = 0 picks it (as in the
//    sampled march), marched again with the sensitivities.
#pragma once

#include <Eigen/Core>

#include "contact/nonlinear_element.h"
#include "hbm/fourier.h"

namespace stickslip {

class FrictionContact3D;

struct AftSamples {
  Eigen::MatrixXd u;  // m x N local relative displacement samples
  Eigen::MatrixXd f;  // m x N local force samples (force on B)
};

enum class AftMethod { kSampled, kEvent, kEventPlanar };

// Where one element's last periodic cycle started, kept by the caller from one call of that element
// to the next (HarmonicBalanceSystem keeps one per contact pair), so that the planar event method
// starts the next cycle there instead of marching from the virgin state: a slipping cycle closes in
// one or two periods instead of four or five, a cycle with a separation in one. The answer does not
// depend on it beyond the closure tolerance (a start that does not close falls back to the virgin
// march). Only kEventPlanar reads and writes it; an empty one (kind kNone) is the virgin start.
struct AftWarmStart {
  enum class Kind { kNone, kSlip, kOpen };
  Kind kind = Kind::kNone;
  double theta = 0.0;         // the phase θ = Ωt the cycle started from (in slip or separation)
  double phi = 0.0;           // slip: the direction of the tangential force there
  Eigen::VectorXd arguments;  // the coefficients and offset of that call
};

class Aft {
 public:
  explicit Aft(FourierBasis basis, AftMethod method = AftMethod::kSampled);
  const FourierBasis& basis() const { return basis_; }
  AftMethod method() const { return method_; }

  // forces: resized to m·nc. jacobian: nullptr to skip, else resized to (m·nc) x (m·nc).
  // offset: size m, or empty for zero. samples: nullptr, or receives the sampled cycle. warm:
  // nullptr, or this element's AftWarmStart (read and updated).
  CycleStatistics evaluate(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                           const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                           Eigen::MatrixXd* jacobian, AftSamples* samples = nullptr,
                           AftWarmStart* warm = nullptr) const;

 private:
  CycleStatistics evaluate_sampled(const NonlinearElement& element,
                                   const Eigen::VectorXd& coefficients,
                                   const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                                   Eigen::MatrixXd* jacobian, AftSamples* samples) const;
  // The event method (event_aft.cpp); false when it does not apply (nothing written then).
  bool evaluate_events(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                       const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                       Eigen::MatrixXd* jacobian, AftSamples* samples, AftWarmStart* warm,
                       CycleStatistics& stats) const;
  // Its general tangential motion in the plane (event_aft_planar.cpp); false as above.
  bool evaluate_planar(const FrictionContact3D& contact, const Eigen::VectorXd& coefficients,
                       const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                       Eigen::MatrixXd* jacobian, AftSamples* samples, AftWarmStart* warm,
                       CycleStatistics& stats) const;

  // ∂u(t_j)/∂c, (m·N) x (m·nc), for element dimension m (constant: u is linear in c).
  const Eigen::MatrixXd& sample_derivative(int m) const;

  FourierBasis basis_;
  AftMethod method_ = AftMethod::kSampled;
  Eigen::MatrixXd analysis_t_;  // Pᵀ, N x nc (contiguous columns for the projections)
  std::vector<Eigen::MatrixXd> sample_derivatives_;  // index m − 1, m = 1..3 precomputed
};

}  // namespace stickslip
