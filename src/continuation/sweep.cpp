#include "continuation/sweep.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "continuation/arclength.h"
#include "core/errors.h"

namespace stickslip {

void validate(const SteppedSweepOptions& o) {
  validate(o.newton, "SteppedSweepOptions.newton.");
  require(o.max_step_halvings >= 0 && o.max_step_halvings <= 30,
          "SteppedSweepOptions.max_step_halvings", std::to_string(o.max_step_halvings),
          "must be in [0, 30]");
  require(o.jump_max_points == 0 || o.jump_max_points >= 2, "SteppedSweepOptions.jump_max_points",
          std::to_string(o.jump_max_points), "must be 0 (no arc-length fallback) or >= 2");
}

namespace {

// The converged points a guess is built from: the last one (g) and the one before (p).
struct SweepHistory {
  int count = 0;  // 0, 1 or 2 valid entries
  double lambda_g = 0, lambda_p = 0;
  Eigen::VectorXd x_g, x_p;

  void reset_to(double lambda, const Eigen::VectorXd& x) {
    count = 0;
    push(lambda, x);
  }
  void push(double lambda, const Eigen::VectorXd& x) {
    if (count > 0) {
      lambda_p = lambda_g;
      x_p = x_g;
    }
    lambda_g = lambda;
    x_g = x;
    count = std::min(count + 1, 2);
  }
  Eigen::VectorXd guess(double lambda, const Eigen::VectorXd& x0, bool secant) const {
    if (count == 0) return x0;
    if (secant && count == 2 && lambda_g != lambda_p) {
      return x_g + ((lambda - lambda_g) / (lambda_g - lambda_p)) * (x_g - x_p);
    }
    return x_g;
  }
};

}  // namespace

ContinuationResult stepped_sweep(const ParametrizedSystem& sys, const Eigen::VectorXd& x0,
                                 std::span<const double> lambdas,
                                 const SteppedSweepOptions& options) {
  validate(options);
  if (x0.size() != sys.size()) {
    throw InvalidInput("stepped_sweep: x0 has size " + std::to_string(x0.size()) +
                       " but the system has size " + std::to_string(sys.size()));
  }
  if (lambdas.empty()) throw InvalidInput("stepped_sweep: lambdas is empty");
  for (double l : lambdas) {
    if (!std::isfinite(l)) throw InvalidInput("stepped_sweep: lambdas contains a non-finite value");
  }

  const double lambda_min = *std::min_element(lambdas.begin(), lambdas.end());
  const double lambda_max = *std::max_element(lambdas.begin(), lambdas.end());
  ContinuationResult result;
  SweepHistory history;
  std::vector<double> failed;
  for (const double target : lambdas) {
    ContinuationPoint point;
    point.lambda = target;
    point.x = history.guess(target, x0, options.secant_predictor);
    point.newton = solve_newton(sys, target, point.x, options.newton);
    std::ostringstream why;  // the failure's one line (ContinuationPoint::failure)
    if (!point.newton.converged()) why << "Newton: " << point.newton.message;

    if (point.newton.converged()) {
      history.push(target, point.x);
    } else if (history.count > 0 && options.max_step_halvings > 0) {
      // Approach the target from the last converged point with halved steps. On failure the
      // history is restored, so the sweep resumes from the last converged requested point.
      const SweepHistory saved = history;
      double lambda = history.lambda_g;
      double step = 0.5 * (target - lambda);
      int halvings = 1;
      while (true) {
        const bool last = std::abs(target - lambda) <= std::abs(step) * (1 + 1e-12);
        const double next = last ? target : lambda + step;
        Eigen::VectorXd y = history.guess(next, x0, options.secant_predictor);
        NewtonSummary s = solve_newton(sys, next, y, options.newton);
        if (s.converged()) {
          history.push(next, y);
          lambda = next;
          if (last) {
            point.x = std::move(y);
            point.newton = std::move(s);
            point.step_halvings = halvings;
            break;
          }
        } else if (halvings >= options.max_step_halvings) {
          why << "; " << halvings << " step halving" << (halvings == 1 ? "" : "s")
              << " did not reach it (the last: " << s.message << ")";
          history = saved;
          break;
        } else {
          step *= 0.5;
          ++halvings;
        }
      }
    }
    if (!point.newton.converged() && history.count > 0 && options.jump_max_points > 0 &&
        target != history.lambda_g) {
      // Follow the curve from the last converged point to the target; it may turn back (folds)
      // as far as the end of the requested range behind the last point.
      const double dl = target - history.lambda_g;
      ArcLengthOptions a;
      a.lambda_start = history.lambda_g;
      a.lambda_end = target;
      a.lambda_return_limit =
          dl > 0 ? std::min(lambda_min, history.lambda_g) : std::max(lambda_max, history.lambda_g);
      // λ scaled by the requested range (as a whole-range continuation would be), not by the
      // step: with a tiny lambda_scale the folds become hairpins and the corrector can hop
      // between branches.
      a.lambda_scale = lambda_max > lambda_min ? lambda_max - lambda_min : std::abs(dl);
      a.initial_step = 0.5 * std::abs(dl);
      a.min_step = 1e-6 * std::abs(dl);
      a.max_step = std::max(4 * std::abs(dl), 0.1 * a.lambda_scale);
      a.max_points = options.jump_max_points;
      a.newton = options.newton;
      ContinuationResult arc = arclength_continuation(sys, history.x_g, a);
      if (arc.completed && arc.points.back().lambda == target) {
        point.x = std::move(arc.points.back().x);
        point.newton = std::move(arc.points.back().newton);
        point.by_arclength = true;
        history.reset_to(target, point.x);  // no secant across a jump
      } else {
        why << "; arc-length fallback: " << arc.message;
      }
    }
    if (!point.newton.converged()) {
      failed.push_back(target);
      point.failure = why.str();
    }
    const bool converged = point.newton.converged();
    result.points.push_back(std::move(point));
    if (options.on_point) {
      const int done = static_cast<int>(result.points.size());
      options.on_point({done, target, static_cast<double>(done) / lambdas.size(), converged,
                        &result.points.back().x});
    }
  }

  result.completed = failed.empty();
  std::ostringstream m;
  m << (lambdas.size() - failed.size()) << " of " << lambdas.size() << " points converged";
  if (!failed.empty()) {
    m << "; not converged at lambda =";
    constexpr std::size_t kListed = 10;  // keep the message one readable line
    for (std::size_t i = 0; i < failed.size() && i < kListed; ++i) m << " " << failed[i];
    if (failed.size() > kListed) m << " ... (" << failed.size() - kListed << " more)";
    for (const ContinuationPoint& p : result.points) {
      if (p.newton.converged()) continue;
      m << "; at lambda = " << p.lambda << ": " << p.failure;  // the first failure's reason
      break;
    }
  }
  result.message = m.str();
  return result;
}

}  // namespace stickslip
