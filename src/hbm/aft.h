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
#pragma once

#include <Eigen/Core>

#include "contact/nonlinear_element.h"
#include "hbm/fourier.h"

namespace stickslip {

struct AftSamples {
  Eigen::MatrixXd u;  // m x N local relative displacement samples
  Eigen::MatrixXd f;  // m x N local force samples (force on B)
};

class Aft {
 public:
  explicit Aft(FourierBasis basis);
  const FourierBasis& basis() const { return basis_; }

  // forces: resized to m·nc. jacobian: nullptr to skip, else resized to (m·nc) x (m·nc).
  // offset: size m, or empty for zero. samples: nullptr, or receives the sampled cycle.
  CycleStatistics evaluate(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                           const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                           Eigen::MatrixXd* jacobian, AftSamples* samples = nullptr) const;

 private:
  // ∂u(t_j)/∂c, (m·N) x (m·nc), for element dimension m (constant: u is linear in c).
  const Eigen::MatrixXd& sample_derivative(int m) const;

  FourierBasis basis_;
  Eigen::MatrixXd analysis_t_;  // Pᵀ, N x nc (contiguous columns for the projections)
  std::vector<Eigen::MatrixXd> sample_derivatives_;  // index m − 1, m = 1..3 precomputed
};

}  // namespace stickslip
