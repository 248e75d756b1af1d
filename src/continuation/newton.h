// Damped Newton–Raphson for R(x, λ) = 0 at a fixed parameter λ (ParametrizedSystem).
//
// Iteration k: solve dR/dx(x_k) Δx = −R(x_k) by dense LU with partial pivoting (LAPACK,
// dense_lu.h), then take x_{k+1} = x_k + s Δx with the largest s ∈ {1, 1/2, 1/4, ...,
// >= min_step_fraction} that gives a sufficient decrease ||R(x_{k+1})|| <= (1 − 1e-4 s) ||R(x_k)||
// (backtracking on the 2-norm of R). The full-step trial is evaluated with R only, and dR/dx is
// asked for at an accepted iterate only when another step follows (the last iterate's dR/dx is
// never needed), unless NewtonOptions.trial_jacobian asks for both at once. A step may reuse the
// previous iterate's factored dR/dx (a chord step, NewtonOptions.reuse_jacobian).
// Watchdog: the full step (s = 1) is also taken when it does not decrease ||R||, up to
// watchdog_steps times in a row and while ||R|| stays below 100 × that of the best iterate (the
// watch point); if no iterate improves on the watch point by then, the solver returns to it and
// backtracks from it. This crosses the kinks of piecewise-smooth residuals (stick/slip switches
// of stiff contacts), where the Newton step is right but ||R|| rises at first.
// Converged when ||R(x_k)||₂ <= tolerance · sys.residual_scale_at(λ) (checked before each step, so an
// initial guess that already satisfies it returns with 0 iterations).
//
// Numerical failure is a returned value, never an exception: NewtonSummary.termination says why
// the solve stopped, and x holds the best iterate found (in ||R||), which residual_norm reports;
// residual_history lists ||R|| at every accepted step, relaxed (watchdog) steps included.
//   kConverged         ||R|| <= tolerance · scale.
//   kMaxIterations     max_iterations steps taken without convergence.
//   kLineSearchFailed  no step fraction down to min_step_fraction decreased ||R|| (e.g. a local
//                      minimum of ||R||, or no root near x).
//   kSingularJacobian  dR/dx has an exact zero pivot or the step is not finite, or no step
//                      fraction decreased ||R|| and the reciprocal condition number estimate of
//                      dR/dx is below min_rcond (estimated only then: it costs about half an LU).
//   kNonFinite         R or dR/dx is NaN/inf at an accepted iterate (incl. the initial guess), or
//                      at every trial point of a line search.
// Bad options, a size mismatch between x and sys.size(), or a residual_scale_at(λ) that is not a
// positive finite number throw InvalidInput.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "continuation/parametrized_system.h"

namespace stickslip {

struct NewtonOptions {
  double tolerance = 1e-8;  // on ||R||₂ relative to sys.residual_scale_at(λ); > 0
  int max_iterations = 30;  // Newton steps (linear solves); >= 1
  // Smallest step fraction tried by the backtracking line search; in (0, 1]. 1 = plain
  // (undamped) Newton that stops with kLineSearchFailed when the full step does not decrease ||R||.
  double min_step_fraction = 1.0 / 64;
  // dR/dx is declared singular when LU's reciprocal condition estimate (1-norm) is below this;
  // in [0, 1).
  double min_rcond = 1e-14;
  // Watchdog (non-monotone) steps: up to this many consecutive full Newton steps may be taken
  // even though they do not decrease ||R||, before returning to the best iterate and
  // backtracking from it. >= 0; 0 = monotone line search only.
  int watchdog_steps = 4;
  // Evaluate dR/dx together with R at every full-step trial (true), or R alone and dR/dx only at
  // accepted, unconverged iterates (false). true pays a Jacobian per solve that is not used for a
  // step, but keeps the one at the solution (arc-length takes its tangent from it) and evaluates
  // R once per iteration instead of twice; false is cheaper when dR/dx costs much more than R
  // (harmonic balance: the AFT derivative march and 𝔾 J_f, about 4 x the residual).
  bool trial_jacobian = false;
  // Chord steps: after a full step that reduced ||R|| at least tenfold, the next step reuses the
  // factored dR/dx of the iterate before instead of evaluating and factoring a new one; the chord
  // step is kept if it again reduces ||R|| tenfold (and may be followed by another), else it is
  // discarded and dR/dx is evaluated at the same iterate. The solution meets the same tolerance;
  // iterations count chord steps. In a stepped sweep most points then take one Newton step and
  // one chord step (reference case: 30 % less time). Not with trial_jacobian (there dR/dx comes
  // with every trial anyway) nor with a structured solve. false: the textbook Newton iteration.
  bool reuse_jacobian = true;
};

// Throws InvalidInput naming the field ("NewtonOptions.tolerance = ...") and the rule it broke.
void validate(const NewtonOptions& options);
// Same, with the fields named "<prefix>tolerance" etc. (for options nested in other options).
void validate(const NewtonOptions& options, std::string_view field_prefix);

enum class NewtonTermination {
  kConverged,
  kMaxIterations,
  kLineSearchFailed,
  kSingularJacobian,
  kNonFinite
};

// "converged", "max_iterations", ...
const char* to_string(NewtonTermination termination);

struct NewtonSummary {
  NewtonTermination termination = NewtonTermination::kMaxIterations;
  int iterations = 0;        // Newton steps taken (linear solves whose step was accepted)
  double residual_norm = 0;  // ||R||₂ at the returned x
  std::string message;       // one line for humans
  // ||R||₂ at the initial guess and after each accepted step (size iterations + 1, except when
  // the initial evaluation is non-finite: then empty).
  std::vector<double> residual_history;
  bool converged() const { return termination == NewtonTermination::kConverged; }
};

// Solves R(x, lambda) = 0 for x in place, starting from the given x (size sys.size()).
NewtonSummary solve_newton(const ParametrizedSystem& sys, double lambda, Eigen::VectorXd& x,
                           const NewtonOptions& options);

}  // namespace stickslip
