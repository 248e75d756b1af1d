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
  // Scale for convergence: Newton at parameter λ stops when ||R|| <= tolerance *
  // residual_scale_at(λ). E.g. the norm of the excitation. Must be > 0 (and should never be a
  // round-off-sized number: the test would then compare round-off with round-off).
  // residual_scale(): a λ-independent scale (arc-length's augmented equation uses it);
  // residual_scale_at(λ): the scale at one λ, by default the same.
  virtual double residual_scale() const { return 1.0; }
  virtual double residual_scale_at(double /*lambda*/) const { return residual_scale(); }

  // Optional structured linear solver for large systems. When has_structured_jacobian() is true,
  // Newton never asks evaluate() for dR_dx; each step instead calls
  //   solve_jacobian(x, λ, rhs, dx):  dx = (dR/dx(x, λ))⁻¹ rhs, to a relative residual
  //   ||dR/dx·dx − rhs|| <= 1e-10 ||rhs|| or better (an inexact Newton step),
  // which returns false when it cannot (singular or not converged). evaluate() must still fill
  // dR_dx when asked (arc-length continuation uses the dense matrix).
  virtual bool has_structured_jacobian() const { return false; }
  virtual bool solve_jacobian(const Eigen::VectorXd& /*x*/, double /*lambda*/,
                              const Eigen::VectorXd& /*rhs*/, Eigen::VectorXd& /*dx*/) const {
    return false;
  }
};

}  // namespace stickslip
