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
// Two methods (AftMethod):
//  - kSampled: the above. The piecewise law sampled at N instants: every transition (stick/slip,
//    lift-off) costs accuracy, O(N^-1.4..-2) in the force coefficients.
//  - kEvent: exact for Jenkins1D and for FrictionContact3D whose tangential motion is collinear
//    (the harmonic coefficient vectors of (u_t1, u_t2) parallel to one direction e; the normal
//    free). The switching functions of the law (μN ∓ τ in stick, the slip rate kt u_e' − μN' in
//    slip, N at lift-off and touchdown) are trigonometric polynomials between transitions; each
//    transition is bracketed on the N-point grid (plus an interior-minimum check per interval)
//    and located to round-off by safeguarded Newton; the force's Fourier integrals are
//    Gauss–Legendre sums per smooth segment, with enough nodes for the segment's trigonometric
//    degree that they are exact to round-off (0.75 H_max L + 10 nodes on a segment of length L).
//    The cycle is the periodic one of the continuous law (the sampled law's limit N → ∞). N sets
//    only the bracketing grid and the samples returned in AftSamples. Jacobian: the force is
//    continuous at every transition, so the boundary terms of the Leibniz rule cancel; the
//    anchor of a stick segment that starts at slip → stick does not depend on the event time
//    (τ_a = σμN(θ_a) and d/dθ_a[σμN − kt u_e](θ_a) = −σ·(slip rate) = 0 there), and the one that
//    starts at touchdown (τ_a = 0) does, through ∂θ_a = −∂N(θ_a)/N'(θ_a), included. The block
//    ∂F_⊥/∂c_⊥ (perpendicular to e in the tangent plane) is the sampled method's at the same N
//    (it shapes Newton's steps only; the forces are exact); the cross blocks vanish by symmetry.
//    Any other element, or a 3D contact whose tangential motion is not collinear, or a fully
//    stuck 3D cycle with a mean tangential offset perpendicular to e: the sampled method, and
//    CycleStatistics::aft_fallback is set so callers can say so.
#pragma once

#include <Eigen/Core>

#include "contact/nonlinear_element.h"
#include "hbm/fourier.h"

namespace stickslip {

struct AftSamples {
  Eigen::MatrixXd u;  // m x N local relative displacement samples
  Eigen::MatrixXd f;  // m x N local force samples (force on B)
};

enum class AftMethod { kSampled, kEvent };

class Aft {
 public:
  explicit Aft(FourierBasis basis, AftMethod method = AftMethod::kSampled);
  const FourierBasis& basis() const { return basis_; }
  AftMethod method() const { return method_; }

  // forces: resized to m·nc. jacobian: nullptr to skip, else resized to (m·nc) x (m·nc).
  // offset: size m, or empty for zero. samples: nullptr, or receives the sampled cycle.
  CycleStatistics evaluate(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                           const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                           Eigen::MatrixXd* jacobian, AftSamples* samples = nullptr) const;

 private:
  CycleStatistics evaluate_sampled(const NonlinearElement& element,
                                   const Eigen::VectorXd& coefficients,
                                   const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                                   Eigen::MatrixXd* jacobian, AftSamples* samples) const;
  // The event method (event_aft.cpp); false when it does not apply (nothing written then).
  bool evaluate_events(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                       const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                       Eigen::MatrixXd* jacobian, AftSamples* samples,
                       CycleStatistics& stats) const;

  // ∂u(t_j)/∂c, (m·N) x (m·nc), for element dimension m (constant: u is linear in c).
  const Eigen::MatrixXd& sample_derivative(int m) const;

  FourierBasis basis_;
  AftMethod method_ = AftMethod::kSampled;
  Eigen::MatrixXd analysis_t_;  // Pᵀ, N x nc (contiguous columns for the projections)
  std::vector<Eigen::MatrixXd> sample_derivatives_;  // index m − 1, m = 1..3 precomputed
};

}  // namespace stickslip
