#include "continuation/newton.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "core/errors.h"
#include "linalg/blas_threads.h"
#include "linalg/dense_lu.h"

namespace stickslip {
namespace {

// Armijo constant of the sufficient-decrease test ||R_new|| <= (1 - c s) ||R||: small, so that
// nearly any decrease is accepted while stagnation (||R_new|| == ||R||) is not.
constexpr double kSufficientDecrease = 1e-4;
// A relaxed (watchdog) step may raise ||R|| up to this factor above the watch point's: beyond it
// the step is taken as a sign of divergence, not of a kink being crossed.
constexpr double kWatchdogGrowth = 100.0;
// A chord step (NewtonOptions.reuse_jacobian) follows a full step that reduced ||R|| at least this
// much, and is kept only if it does so again: a step that contracts ||R|| tenfold is in the
// region where the old dR/dx still steers well, and a kept chord step never converges slower
// than that.
constexpr double kChordContraction = 0.1;

std::string str(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

bool all_finite(const Eigen::VectorXd& v) { return v.allFinite(); }

}  // namespace

void validate(const NewtonOptions& o, std::string_view prefix) {
  const std::string p(prefix);
  require(std::isfinite(o.tolerance) && o.tolerance > 0, p + "tolerance", str(o.tolerance),
          "must be finite and > 0");
  require(o.max_iterations >= 1, p + "max_iterations", std::to_string(o.max_iterations),
          "must be >= 1");
  require(o.min_step_fraction > 0 && o.min_step_fraction <= 1, p + "min_step_fraction",
          str(o.min_step_fraction), "must be in (0, 1]");
  require(o.watchdog_steps >= 0, p + "watchdog_steps", std::to_string(o.watchdog_steps),
          "must be >= 0");
  require(o.min_rcond >= 0 && o.min_rcond < 1, p + "min_rcond", str(o.min_rcond),
          "must be in [0, 1)");
}

void validate(const NewtonOptions& o) { validate(o, "NewtonOptions."); }

const char* to_string(NewtonTermination t) {
  switch (t) {
    case NewtonTermination::kConverged:
      return "converged";
    case NewtonTermination::kMaxIterations:
      return "max_iterations";
    case NewtonTermination::kLineSearchFailed:
      return "line_search_failed";
    case NewtonTermination::kSingularJacobian:
      return "singular_jacobian";
    case NewtonTermination::kNonFinite:
      return "non_finite";
  }
  return "unknown";
}

NewtonSummary solve_newton(const ParametrizedSystem& sys, double lambda, Eigen::VectorXd& x,
                           const NewtonOptions& options) {
  validate(options);
  const int n = sys.size();
  if (x.size() != n) {
    throw InvalidInput("solve_newton: x has size " + std::to_string(x.size()) +
                       " but the system has size " + std::to_string(n));
  }
  const double scale = sys.residual_scale_at(lambda);
  require(std::isfinite(scale) && scale > 0, "ParametrizedSystem::residual_scale_at()", str(scale),
          "must be finite and > 0");
  const double threshold = options.tolerance * scale;

  NewtonSummary summary;
  Eigen::VectorXd x_watch, R_watch;  // the watch point: the best iterate so far
  double r_watch = std::numeric_limits<double>::infinity();
  auto finish = [&](NewtonTermination t, const std::string& why) {
    summary.termination = t;
    if (t != NewtonTermination::kConverged && x_watch.size() == n &&
        r_watch < summary.residual_norm) {  // a relaxed step left the best iterate: return it
      x = x_watch;
      summary.residual_norm = r_watch;
    }
    std::ostringstream m;
    m << to_string(t) << " after " << summary.iterations
      << " iterations at lambda = " << str(lambda) << ": ||R|| = " << str(summary.residual_norm)
      << " (threshold " << str(threshold) << ")";
    if (!why.empty()) m << "; " << why;
    summary.message = m.str();
    return summary;
  };

  Eigen::VectorXd R(n), R_trial(n), dx(n), x_trial(n);
  // Structured systems solve their own Newton systems (no dense dR/dx here).
  const bool structured = sys.has_structured_jacobian();
  Eigen::MatrixXd J(structured ? 0 : n, structured ? 0 : n), J_trial;
  Eigen::MatrixXd* const J_out = structured ? nullptr : &J;
  sys.evaluate(x, lambda, R, J_out, nullptr);
  STICKSLIP_VERIFY(R.size() == n && (structured || (J.rows() == n && J.cols() == n)),
                   "ParametrizedSystem::evaluate returned outputs of the wrong size");
  bool have_jacobian = true;
  if (!all_finite(R)) {
    summary.residual_norm = std::numeric_limits<double>::quiet_NaN();
    return finish(NewtonTermination::kNonFinite, "R is not finite at the initial guess");
  }
  double r = R.norm();
  summary.residual_norm = r;
  summary.residual_history.push_back(r);

  DenseLu lu;
  // One BLAS thread for the whole solve (the LUs and whatever BLAS the system's evaluate uses):
  // at Newton's sizes threads only spin on a busy machine.
  const ScopedBlasThreads single_thread(1);
  auto watch_here = [&] {  // the current iterate becomes the watch point
    x_watch = x;
    R_watch = R;
    r_watch = r;
  };
  watch_here();
  int relaxed_steps = 0;  // relaxed steps taken since the watch point
  bool chord_ready = false;  // the next step may reuse the factored dR/dx
  while (true) {
    if (r <= threshold) return finish(NewtonTermination::kConverged, "");
    if (summary.iterations >= options.max_iterations) {
      return finish(NewtonTermination::kMaxIterations, "");
    }
    if (chord_ready) {
      // Chord step: the last factored dR/dx again (see NewtonOptions.reuse_jacobian). Kept only if
      // it contracts ||R|| as strongly as the step before; otherwise discarded, and a fresh
      // dR/dx is evaluated at the same iterate below.
      chord_ready = false;
      dx = lu.solve(-R);
      if (all_finite(dx)) {
        x_trial = x + dx;
        sys.evaluate(x_trial, lambda, R_trial, nullptr, nullptr);
        const double r_trial = R_trial.norm();
        if (all_finite(R_trial) && r_trial <= kChordContraction * r) {
          x.swap(x_trial);
          R.swap(R_trial);
          r = r_trial;
          watch_here();
          relaxed_steps = 0;
          chord_ready = true;
          ++summary.iterations;
          summary.residual_norm = r;
          summary.residual_history.push_back(r);
          continue;
        }
      }
    }
    if (structured) {
      if (!sys.solve_jacobian(x, lambda, -R, dx)) {
        return finish(NewtonTermination::kSingularJacobian, "the structured solve of dR/dx failed");
      }
    } else {
      if (!have_jacobian) {
        sys.evaluate(x, lambda, R, &J, nullptr);
        have_jacobian = true;
      }
      if (!J.allFinite()) return finish(NewtonTermination::kNonFinite, "dR/dx is not finite");
      if (!lu.factor(J)) {  // J is finite here: an exact zero pivot
        return finish(NewtonTermination::kSingularJacobian, "dR/dx has an exact zero pivot");
      }
      have_jacobian = false;  // J now holds the factors
      dx = lu.solve(-R);
    }
    if (!all_finite(dx)) {
      return finish(NewtonTermination::kSingularJacobian, "the Newton step is not finite");
    }

    // 1. The full step, evaluated (R only unless trial_jacobian). Accepted if it decreases ||R||
    //    enough, or, as a relaxed step (watchdog), if fewer than watchdog_steps relaxed steps have
    //    been taken since the watch point (the best iterate) and ||R|| stays below
    //    kWatchdogGrowth times the watch point's. A relaxed iterate that decreases ||R|| below the
    //    watch point's becomes the new watch point.
    // 2. Otherwise, return to the watch point (if we left it) and backtrack from there: s = 1/2,
    //    1/4, ... with R only; the Jacobian is then computed at the start of the next iteration.
    bool accepted = false;
    bool any_finite = false;
    x_trial = x + dx;
    const bool trial_jacobian = options.trial_jacobian && !structured;
    sys.evaluate(x_trial, lambda, R_trial, trial_jacobian ? &J_trial : nullptr, nullptr);
    if (all_finite(R_trial)) {
      any_finite = true;
      const double r_trial = R_trial.norm();
      const bool decrease = r_trial <= (1 - kSufficientDecrease) * r;
      const bool relaxed = !decrease && relaxed_steps < options.watchdog_steps &&
                           r_trial <= kWatchdogGrowth * r_watch;
      if (decrease || relaxed) {
        chord_ready = options.reuse_jacobian && !structured && !trial_jacobian &&
                      relaxed_steps == 0 && r_trial <= kChordContraction * r;
        x.swap(x_trial);
        R.swap(R_trial);
        if (trial_jacobian) J.swap(J_trial);
        have_jacobian = trial_jacobian;
        r = r_trial;
        accepted = true;
        if (r <= (1 - kSufficientDecrease) * r_watch) {
          watch_here();
          relaxed_steps = 0;
        } else {
          ++relaxed_steps;
        }
      }
    }
    if (!accepted) {
      if (relaxed_steps > 0) {  // back to the watch point; its Newton step again
        x = x_watch;
        R = R_watch;
        r = r_watch;
        relaxed_steps = 0;
        if (structured) {
          sys.evaluate(x, lambda, R, nullptr, nullptr);
          if (!sys.solve_jacobian(x, lambda, -R, dx)) dx.setZero();
        } else {
          sys.evaluate(x, lambda, R, &J, nullptr);
          if (J.allFinite() && lu.factor(J)) {
            dx = lu.solve(-R);
          } else {
            dx.setZero();
          }
        }
      }
      for (double s = 0.5; s >= options.min_step_fraction * (1 - 1e-12); s *= 0.5) {
        x_trial = x + s * dx;
        sys.evaluate(x_trial, lambda, R_trial, nullptr, nullptr);
        if (!all_finite(R_trial)) continue;
        any_finite = true;
        const double r_trial = R_trial.norm();
        if (r_trial <= (1 - kSufficientDecrease * s) * r) {
          x.swap(x_trial);
          R.swap(R_trial);
          have_jacobian = false;
          r = r_trial;
          accepted = true;
          watch_here();
          break;
        }
      }
    }
    if (!accepted && !structured && lu.factored() && !(lu.rcond() >= options.min_rcond)) {
      // The step failed from a (nearly) singular dR/dx: say so rather than "line search failed".
      return finish(NewtonTermination::kSingularJacobian, "rcond(dR/dx) = " + str(lu.rcond()) +
                                                              " < min_rcond = " +
                                                              str(options.min_rcond));
    }
    if (!accepted) {
      return finish(
          any_finite ? NewtonTermination::kLineSearchFailed : NewtonTermination::kNonFinite,
          any_finite ? "no step fraction >= " + str(options.min_step_fraction) + " decreased ||R||"
                     : "R is not finite at any trial point of the line search");
    }
    ++summary.iterations;
    summary.residual_norm = r;
    summary.residual_history.push_back(r);
  }
}

}  // namespace stickslip
