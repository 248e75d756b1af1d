// Frequency response of a HarmonicBalanceSystem: a stepped sweep (NOVA-style list of Ω, previous
// point as the guess, step halving on failure) or pseudo arc-length continuation in (u, Ω)
// through turning points, both from continuation/. The first guess is the linear stuck (or free)
// solution at the first frequency (HarmonicBalanceSystem::linear_guess).
//
// Per point: every master DOF's harmonics, contact forces per pair and harmonic in
// local axes (force on B, rows of the pair's frame) and global axes (+Rᵀ f, on node B; node A
// receives the negative), relative displacement harmonics, the cycle statistics (stick / slip /
// separation fractions, dissipated energy per cycle), Newton iterations, residual, convergence;
// on request the sampled cycle (time history, hysteresis loop) of chosen pairs. Complex harmonics
// follow X_k = a_k − i b_k; columns are output_harmonics() (0 first). Ω in rad/s.
// Stepped sweep: the points the sweep could not solve (typically just past a fold of a response
// with heavy lift-off, where the sweep's branch ends and Newton stalls at a local minimum of ||R||)
// get a second chance: each run of them is swept again backwards from the converged point after
// it (the branch a sweep in the other direction follows), then both ways once more from its
// converged neighbours, and the rest are solved from scratch like the first point (linear guess,
// excitation ramp). FrequencyResponse.message says how many were recovered so.
// Points that still failed are kept, with converged = false.
// For a system with a structured Newton solve (HarmonicBalanceSystem::has_structured_jacobian,
// large systems) the stepped sweep's arc-length fallback (SteppedSweepOptions.jump_max_points) is
// off, in the sweep, its retries and the first point's ramp: it would need the dense dR/dx.
#pragma once

#include <complex>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "continuation/arclength.h"
#include "continuation/sweep.h"
#include "hbm/harmonic_balance.h"
#include "hbm/hill_stability.h"

namespace stickslip {

// Check of the uncoupled static formulation (static: uncoupled freezes the static state u0, f0;
// it is exact only when the vibration leaves the static balance alone, i.e. when each pair's
// cycle-mean force f̄ (the AFT's own harmonic 0 over the cycle) equals its frozen f0). Per pair:
//   static_mismatch = ||f̄ − f0|| / max(||f0||, max_t ||f(t)||)   (local axes, 2-norms),
// and a point is flagged when some pair's mismatch exceeds kStaticMismatchThreshold or some pair
// separates over part of the cycle (separates_in_part; N = 0 over part of the cycle: its mean normal force then exceeds the frozen one, and
// the mean approach shifts). Stuck, closed cycles give f̄ = f0 to round-off (f is linear about
// f0 and u has no mean beyond u0); a cycle that slips symmetrically about f0 is not flagged
// either, and rightly: its harmonic-0 balance holds. With static: coupled nothing is checked.
inline constexpr double kStaticMismatchThreshold = 1e-2;  // 1 % of the pair's force scale
// Separation that the frozen static state cannot represent: over part of the cycle. A pair open
// over the whole cycle has f̄ = 0, which is right when its static state is open too (f0 = 0: a
// pair that a computed preload leaves open) and is caught by the mismatch otherwise.
inline bool separates_in_part(const CycleStatistics& cycle) {
  return cycle.separation_fraction > 0 && cycle.separation_fraction < 1;
}

struct PairResponse {
  Eigen::MatrixXcd displacement_local;  // m x nh, u = R (x_A − x_B)
  Eigen::MatrixXcd force_local;         // m x nh, force on B in the pair frame
  Eigen::MatrixXcd force_global;        // k x nh, force on B in global axes (+Rᵀ f)
  CycleStatistics cycle;
  AftSamples history;  // filled for the requested pairs only (u, f: m x N over one period)
  // static: uncoupled only (else empty / 0): the cycle-mean local force f̄ (m) and the mismatch
  // against the frozen f0 (see kStaticMismatchThreshold).
  Eigen::VectorXd cycle_mean_force;
  double static_mismatch = 0.0;
};

struct FrequencyPoint {
  double omega = 0.0;  // rad/s
  bool converged = false;
  int iterations = 0;
  double residual_norm = 0.0;
  double residual_scale = 1.0;  // Newton's scale at this Ω (residual_scale_at), m
  std::string message;
  Eigen::VectorXd unknowns;  // the solution vector (layout of harmonic_balance.h)
  Eigen::MatrixXcd master;   // ndof x nh master-DOF harmonics
  std::vector<PairResponse> pairs;
  // static: uncoupled: the largest pair mismatch, its pair (−1: none) and whether the frozen
  // static state is flagged as wrong at this point (mismatch above the threshold or separation).
  double static_mismatch = 0.0;
  int static_worst_pair = -1;
  bool static_warning = false;
  // FrequencyResponseOptions.stability only: Hill's method at this (converged) point
  // (hill_stability.h); stability_computed false otherwise and for points that did not converge.
  bool stability_computed = false;
  FloquetSummary floquet;
};

// Bifurcations along an arc-length continuation (FrequencyResponseOptions.bifurcations):
//   fold             a turning point in Ω: the tangent's Ω-component changes sign between two
//                    consecutive points;
//   branch_point     a real Floquet multiplier crosses +1 where no fold is (symmetry breaking,
//                    transcritical);
//   period_doubling  a real multiplier crosses −1;
//   neimark_sacker   a complex pair crosses the unit circle.
// The last three need analysis.stability (Hill's exponents at every point): a crossing is a
// change of the number of exponents of one MultiplierKind (hill_stability.h) outside the circle
// between two consecutive points. Each is then located by bisection on the arc between the two
// points (bisect_on_arc): the test function is the tangent's Ω-component for a fold, the largest
// Re μ of the crossing kind (Hill at every bisection point) for the others. A stepped sweep gets
// none (it has no arc to bisect on, and it jumps at folds).
enum class BifurcationType { kFold, kBranchPoint, kPeriodDoubling, kNeimarkSacker };
const char* to_string(BifurcationType type);  // "fold", "branch_point", ...

struct BifurcationOptions {
  bool enabled = true;
  // The bisection's final bracket, relative to the continuation's lambda_scale (arclength.h):
  // the located Ω is within tolerance · lambda_scale of the curve's exact zero of the test
  // function (and the unknowns within tolerance · x_scale). > 0.
  double tolerance = 1e-7;
  int max_bisections = 60;  // >= 0
};
void validate(const BifurcationOptions& options);

// Response peaks located on an arc-length continuation (FrequencyResponseOptions.peaks). The
// largest sampled amplitude is only as close to the true peak as the points are dense, and the
// curvature-controlled steps (arclength.h) are sparse. For each requested master DOF, A = |X| of
// its first dynamic output harmonic: the point of largest A among the converged points, then the
// maximum of A along the curve between that point and the neighbour towards which A still rises,
// by bisection on the arc (bisect_on_arc) on g = dA²/dσ, the derivative along the curve's unit
// tangent (central difference of A² along the tangent, in the scaled variables): g > 0 before the
// maximum, < 0 after. Not located (the sampled maximum is given, with the reason): the maximum at
// the first or the last point (the peak may lie outside the window), a neighbour that did not
// converge, no sign change of g on either side (a peak on a corner of the curve, where a sample
// switches between stick, slip and separation exactly there), or a failed bisection. A stepped
// sweep gets none (its points are the user's frequencies, and it jumps at folds).
struct PeakOptions {
  std::vector<int> dofs{};  // master DOF indices (each in [0, master_dofs)); empty = none
  // The bisection's final bracket, relative to the continuation's lambda_scale: > 0.
  double tolerance = 1e-8;
  int max_bisections = 60;  // >= 0
};
void validate(const PeakOptions& options, int master_dofs);

struct ResponsePeak {
  int dof = -1;            // the master DOF
  int sampled_point = -1;  // the converged point of largest amplitude; -1: none converged
  bool located = false;    // the bisection met PeakOptions.tolerance
  double omega = 0.0;      // rad/s: the located maximum, else the sampled one's
  double amplitude = 0.0;  // |X|, m: likewise
  double bracket = 0.0;    // the final bracket, rad/s (arc length in units of Ω)
  std::string message;
};

enum class ContinuationMethod { kSteppedSweep, kArcLength };
enum class InitialGuess { kLinearStuck, kLinearFree };

struct FrequencyResponseOptions {
  ContinuationMethod method = ContinuationMethod::kSteppedSweep;
  std::vector<double> omegas;  // stepped sweep: the frequencies, rad/s (not empty)
  SteppedSweepOptions sweep;   // stepped sweep
  ArcLengthOptions arclength;  // arc-length: lambda = Ω
  InitialGuess initial_guess = InitialGuess::kLinearStuck;
  std::vector<int> history_pairs{};  // pairs whose sampled cycle is kept per point
  bool stability = false;            // Hill's method at every converged point
  HillOptions hill{};
  BifurcationOptions bifurcations{};  // arc-length only
  PeakOptions peaks{};                // arc-length only
};

struct Bifurcation {
  BifurcationType type = BifurcationType::kFold;
  int after_point = 0;   // between points[after_point] and points[after_point + 1]
  bool located = false;  // the bisection met BifurcationOptions.tolerance
  double bracket = 0.0;  // the final bracket, rad/s (arc length in units of Ω)
  // The outputs at the located point (evaluate_point; with stability its Floquet summary too).
  // When the bisection failed: the point it stopped at, or the point before (message says).
  FrequencyPoint point;
  // With stability: the multiplier of the crossing kind of largest modulus at the point (≈ 1,
  // −1 or on the unit circle); NaN without.
  std::complex<double> multiplier{std::numeric_limits<double>::quiet_NaN(),
                                  std::numeric_limits<double>::quiet_NaN()};
  std::string message;
};

struct FrequencyResponse {
  std::vector<FrequencyPoint> points;
  std::vector<Bifurcation> bifurcations;  // in the order of the curve (arc-length only)
  std::vector<ResponsePeak> peaks;        // one per PeakOptions.dofs, in order (arc-length only)
  std::vector<int> harmonics;  // output harmonics (columns of every complex matrix)
  bool completed = false;
  std::string message;
};

// Throws InvalidInput on bad options (empty omegas, history pair out of range, ...).
FrequencyResponse frequency_response(const HarmonicBalanceSystem& system,
                                     const FrequencyResponseOptions& options);

// Outputs at one solution (x, Ω).
FrequencyPoint evaluate_point(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                              double omega, const std::vector<int>& history_pairs = {});

}  // namespace stickslip
