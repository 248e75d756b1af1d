// Stepped parameter sweep (NOVA-style fmin:step:fmax) of R(x, λ) = 0, and the result type shared
// with arc-length continuation (continuation/arclength.h).
//
// stepped_sweep solves R(x, λ_i) = 0 with solve_newton for each requested λ_i in the given order
// (increasing, decreasing or arbitrary). The initial guess is the solution at the last converged
// point (x0 for the first point), or optionally the secant extrapolation through the last two
// converged points. If Newton fails at λ_i, the step from the last converged point (λ_g, x_g) is
// halved (at most max_step_halvings times) and λ_i is approached through intermediate
// parameters, each solved from the previous one; intermediate solutions are not returned.
// If that fails too, and jump_max_points > 0, the solution curve is followed by arc-length
// continuation (arclength.h) from (λ_g, x_g) until it first reaches λ_i: past a fold this goes
// round the fold and the unstable branch behind it and lands on the branch the response jumps to
// (the curve may go back no further than the far end of the requested range).
// If λ_i is still not reached, the point is REPORTED (newton.converged() == false, x = the last
// iterate of the direct attempt from (λ_g, x_g) at λ_i) and the sweep goes on from (λ_g, x_g):
// the result has exactly one point per requested λ, in order. Before any point has converged
// there is no good start to halve from: each λ_i is then tried directly from x0.
// On a multivalued response the sweep follows the branch it is on until that branch ends at a
// fold, then jumps to another branch: the hysteresis of a physical sweep.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "continuation/newton.h"
#include "continuation/parametrized_system.h"

namespace stickslip {

struct ContinuationPoint {
  double lambda = 0;
  Eigen::VectorXd x;
  // The Newton solve that produced x. For arc-length points, the corrector on the augmented
  // system (R; arc-length equation): residual_norm includes the arc-length equation scaled by
  // sys.residual_scale(), which is ~0 at convergence.
  NewtonSummary newton;
  // stepped_sweep only: how many times the step had to be halved to reach lambda (0 = direct),
  // and whether the arc-length fallback reached it (typically a jump after a fold).
  int step_halvings = 0;
  bool by_arclength = false;
  // stepped_sweep only, for a point that did not converge: why, in one line — Newton's own
  // message at the point, how far the step halvings got, and what stopped the arc-length
  // fallback (its message); empty for a converged point.
  std::string failure;
  // arclength_continuation only: the unit tangent of the curve at this point in the scaled
  // variables y = (x / x_scale, λ / lambda_scale) (size n + 1, λ last), oriented in the direction
  // of travel; empty for a point clipped onto lambda_end or the return limit, and in a stepped
  // sweep. Its last component changes sign at a fold (a turning point in λ).
  Eigen::VectorXd tangent;
};

struct ContinuationResult {
  std::vector<ContinuationPoint> points;
  // stepped_sweep: every requested point converged. arclength_continuation: the branch was
  // followed to lambda_end.
  bool completed = false;
  std::string message;  // one line for humans: how it ended, which points failed
  // arclength_continuation only: the scales it used (arclength.h, "Scaling"); 0 otherwise.
  double x_scale = 0, lambda_scale = 0;
};

// Progress of a sweep or continuation, reported after each point it returns (to drive a progress
// bar). points: points returned so far; lambda: the parameter of the last one; fraction: the part
// of the requested range done, in [0, 1] (stepped: points / requested; arc-length: how far λ
// got from lambda_start towards lambda_end); converged: whether the last point converged; x: its
// solution (valid during the call only; null when the caller has none).
struct ContinuationProgress {
  int points = 0;
  double lambda = 0;
  double fraction = 0;
  bool converged = true;
  const Eigen::VectorXd* x = nullptr;
};
// Called on the solving thread; it must not throw. Empty = no reports.
using ProgressCallback = std::function<void(const ContinuationProgress&)>;

struct SteppedSweepOptions {
  NewtonOptions newton;
  int max_step_halvings = 4;      // >= 0; 0 = no retry
  bool secant_predictor = false;  // guess by extrapolating the last two converged points
  // Points allowed to the arc-length fallback per failed point; 0 disables it, else >= 2.
  // It uses lambda_scale = L = the requested λ range, x_scale = ||x_g||, steps from |Δλ|/2
  // (Δλ = λ_i − λ_g), between |Δλ|/1e6 and max(4|Δλ|, L/10), and the default step guards.
  int jump_max_points = 200;
  ProgressCallback on_point{};  // after each requested point (converged or reported)
};

// Throws InvalidInput naming the field ("SteppedSweepOptions.max_step_halvings = -1. ...").
void validate(const SteppedSweepOptions& options);

// x0: initial guess for lambdas[0] (size sys.size()). lambdas: non-empty, finite.
ContinuationResult stepped_sweep(const ParametrizedSystem& sys, const Eigen::VectorXd& x0,
                                 std::span<const double> lambdas,
                                 const SteppedSweepOptions& options);

}  // namespace stickslip
