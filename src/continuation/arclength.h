// Pseudo arc-length continuation (Keller) of the solution curve of R(x, λ) = 0 in (x, λ), from
// lambda_start towards lambda_end, following turning points (folds) where λ reverses.
//
// Scaling. The curve is followed in the scaled variables y = (x / x_scale, λ / lambda_scale), and
// step lengths are measured in units of λ:
//     Δs = sqrt( Δλ² + (lambda_scale / x_scale)² ||Δx||₂² ),
// i.e. a change of ||x|| by x_scale counts as much as a change of λ by lambda_scale. On a part of
// the curve where x hardly changes, a step Δs moves λ by about Δs; through a resonance or a fold
// the step is spent on x. Defaults (0 = automatic): lambda_scale = |lambda_end − lambda_start|,
// x_scale = ||x|| of the first point (1 if that is 0). For a frequency response that starts off
// resonance, ||x_first|| is much smaller than the peak and the arc length through the peak is
// then long (many points at max_step): set x_scale to the expected peak amplitude (e.g. from the
// linear response) to spend fewer points there.
//
// Algorithm.
//  1. The first point is solve_newton(sys, lambda_start, x0). If it fails, the result holds that
//     one (not converged) point and completed = false.
//  2. Tangent t (unit, in y): [dR/dy; bᵀ] t = [0; 1] with b = t_prev (b = e_λ · sign(lambda_end −
//     lambda_start) at the first point), then normalised; b keeps the orientation (t · t_prev > 0).
//  3. Predictor y_p = y_k + Δσ t_k with Δσ = Δs / lambda_scale. Corrector: solve_newton (options
//     .newton) on the n+1 equations [R(x, λ); residual_scale · (t_kᵀ (y − y_k) − Δσ)] = 0.
//  4. A corrector that fails, a corrected point farther than max_correction · Δσ from the predicted
//     one, a singular bordered matrix, or a tangent turning by more than max_turn_angle (radians,
//     between t_k and t_{k+1}) rejects the step (the distance and angle tests guard against
//     jumping to another branch): Δs is halved and the step retried. Below min_step the
//     continuation stops with completed = false. An accepted step multiplies Δs by step_growth if
//     the corrector needed fewer than target_newton_iterations iterations and by 1/2 if more,
//     within [min_step, max_step]. With target_turn_angle > 0 (curvature control) the factor is
//     also at most target_turn_angle / (the angle the tangent turned in the accepted step), within
//     [1/2, step_growth]: steps grow where the curve is straight and shrink where it bends (peaks,
//     folds); the smaller of the two factors wins. With max_lambda_step > 0 a step is also at most
//     max_lambda_step / |t_λ| (t_λ the tangent's λ-component), and a step whose λ advanced by
//     more than 1.25 max_lambda_step (the curve bent towards λ within it) is retried shorter:
//     λ advances by at most that per step, so a stretch cannot jump over a feature in λ, while a
//     step along a part of the curve that moves x at nearly constant λ (a resonance's flanks) is
//     bounded only by max_step. Corners. A piecewise-smooth R (friction contact sampled in time: a
//     sample that switches between stick, slip and separation is a kink) has a curve with corners,
//     where the tangent turns by a finite angle and the correction is proportional to the step
//     however small the step is. A step rejected by the distance or angle test is therefore
//     accepted as crossing a corner when the retry at half the step (from the same point) fails the
//     tests too, but its new tangent agrees with the first attempt's to within a quarter of its
//     turn (on a smooth curve they differ by about half the turn) and its correction relative to
//     the step has not grown (it doubles when the corrector lands on another branch).
//  Cost per accepted step: one LU of size n+1 per corrector iteration plus one for the tangent.
//  5. Stop when a point lands beyond lambda_end (that point is replaced by the solution at exactly
//     lambda_end, from an interpolated guess; completed = true), when λ falls back behind
//     lambda_return_limit (default lambda_start; clipped likewise onto it; completed = false), or
//     after max_points points (completed = false). lambda_end < lambda_start sweeps downwards.
// Every returned point is converged (except a failed first point, see 1.). The message says how
// the continuation ended.
#pragma once

#include <functional>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "continuation/newton.h"
#include "continuation/parametrized_system.h"
#include "continuation/sweep.h"

namespace stickslip {

struct ArcLengthOptions {
  double lambda_start = 0, lambda_end = 0;  // finite, different
  // Arc-length steps in units of λ (see Scaling): 0 < min_step <= initial_step <= max_step.
  double initial_step = 0, min_step = 0, max_step = 0;
  int max_points = 10000;            // >= 2, including the first point
  int target_newton_iterations = 4;  // >= 1: corrector iterations the step control aims at
  NewtonOptions newton;              // for the first point, the corrector and the clipping
  double x_scale = 0;                // >= 0; 0 = ||x_first|| (1 if 0)
  double lambda_scale = 0;           // >= 0; 0 = |lambda_end − lambda_start|
  double max_turn_angle = 0.5;       // radians, in (0, π): largest angle between two tangents
  // Largest distance between corrected and predicted point, relative to the step (in y); > 0.
  // On a smooth curve the correction is O(step² · curvature); a long one means the corrector
  // went to another part of the curve.
  double max_correction = 1.0;
  double step_growth = 1.5;  // >= 1: step factor after an easy corrector
  // Curvature control (see 4.): radians, in [0, max_turn_angle); 0 = off.
  double target_turn_angle = 0;
  // Largest advance of λ per step (see 4.), units of λ; >= 0, 0 = no such bound.
  double max_lambda_step = 0;
  // How far back λ may go behind lambda_start after a fold before the continuation stops: a value
  // on the far side of lambda_start from lambda_end, or NaN (default) for lambda_start itself.
  double lambda_return_limit = std::numeric_limits<double>::quiet_NaN();
  ProgressCallback on_point{};  // after each returned point; fraction from λ's progress
};

// Throws InvalidInput naming the field ("ArcLengthOptions.min_step = ...") and the rule it broke.
void validate(const ArcLengthOptions& options);

// x0: initial guess of the solution at lambda_start (size sys.size()). Every point but a clipped
// one carries its tangent; the result carries the scales used (sweep.h).
ContinuationResult arclength_continuation(const ParametrizedSystem& sys, const Eigen::VectorXd& x0,
                                          const ArcLengthOptions& options);

// Locating a zero of a test function g along the curve between two of its points a and b (two
// consecutive points of arclength_continuation: a fold where the tangent's λ-component changes
// sign, a Floquet multiplier crossing the unit circle).
// The curve between a and b is parametrised by the planes eᵀ(y − y_a) = s · |y_b − y_a|, s ∈ [0,
// 1], e the unit chord (y scaled as in "Scaling" above with the scales given here): each point is
// the corrector's solution of [R(x, λ) = 0; the plane] from the bracket's midpoint, with its
// tangent (oriented along e). Bisection on s keeps the sign change of g; it stops when the
// bracket's ends are closer than `tolerance` (distance in y times lambda_scale, the units of the
// arc-length steps), and the result is then the curve's point at the zero of g interpolated
// linearly between the bracket's ends. Since Δs bounds |Δλ| and (lambda_scale / x_scale) ||Δx||,
// the located λ and x are within the bracket of the exact zero (for a smooth g, the interpolation
// is within O(bracket²)). Cost: one corrector solve and one tangent per bisection; about log2(|y_b
// − y_a| · lambda_scale / tolerance) of them. The chord plane cuts the arc once when the tangent
// turns by less than 90° between a and b (the continuation's turn guard keeps it below
// max_turn_angle).
using CurveTestFunction = std::function<double(const ContinuationPoint&)>;

struct ArcBisectionOptions {
  double tolerance = 0;                  // > 0: bracket length, units of λ
  int max_bisections = 60;               // >= 0
  double x_scale = 1, lambda_scale = 1;  // > 0: the continuation's (ContinuationResult)
  NewtonOptions newton;                  // the corrector's
};
void validate(const ArcBisectionOptions& options);

struct ArcBisectionResult {
  bool located = false;     // the bracket met the tolerance and the estimate was solved
  ContinuationPoint point;  // the estimate (located), else the last point solved
  double g = 0;             // g at point (located)
  double bracket = 0;       // the final bracket's length, units of λ
  int solves = 0;           // corrector solves
  std::string message;
};

// g_a, g_b: g at a and b, of opposite signs (else InvalidInput); g is called at every point
// solved. A failed corrector or a non-finite g ends the search with located = false (a value,
// not an exception).
ArcBisectionResult bisect_on_arc(const ParametrizedSystem& sys, const ContinuationPoint& a,
                                 double g_a, const ContinuationPoint& b, double g_b,
                                 const CurveTestFunction& g, const ArcBisectionOptions& options);

}  // namespace stickslip
