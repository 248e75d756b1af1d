// The interface every continuation and Newton algorithm sees: a smooth system R(x, λ) = 0 with
// x ∈ Rⁿ and one scalar parameter λ (for frequency response, λ = Ω in rad/s).
// Algorithms know nothing else about the problem (STYLE.md, guideline 4).
#pragma once

#include <Eigen/Core>

namespace stickslip {

class ParametrizedSystem {
 public:
  virtual ~ParametrizedSystem() = default;
  virtual int size() const = 0;  // n
  // R(x, λ) into R (size n). Optional outputs (nullptr = skip): dR_dx (n x n), dR_dlambda (n).
  // evaluate() sizes its outputs (callers may pass empty objects). Newton asks for dR_dx only;
  // arc-length continuation asks for dR_dx and dR_dlambda together. Non-finite values are allowed
  // (e.g. outside the domain of R): the solvers report them (NewtonTermination::kNonFinite) or
  // backtrack from them.
  virtual void evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& R,
                        Eigen::MatrixXd* dR_dx, Eigen::VectorXd* dR_dlambda) const = 0;
  // Scale for convergence: Newton stops when ||R|| <= tolerance * residual_scale().
  // E.g. the norm of the excitation. Must be > 0.
  virtual double residual_scale() const { return 1.0; }
};

}  // namespace stickslip
