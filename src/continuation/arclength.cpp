#include "continuation/arclength.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>

#include <Eigen/LU>

#include "core/errors.h"

namespace stickslip {
namespace {

// Step factor after a corrector that needed more than the target iterations.
constexpr double kStepShrink = 0.5;
// A corner of a piecewise-smooth curve (see arclength.h). A step that crosses a corner turns the
// tangent by the corner's angle and needs a correction proportional to the step, however small the
// step: halving never satisfies the guards, and the continuation would creep up to the corner
// until the step is below min_step. So when a step rejected by a guard is retried at half the
// length from the same point and both land beyond the corner, the second is accepted as a corner
// if its tangent agrees with the first's to within this fraction of its turn (on a smooth curve the
// two differ by about half the turn) and its correction, relative to the step, did not grow (it
// doubles when the corrector lands on another branch at a fixed distance).
constexpr double kCornerTangentAgreement = 0.25;
// A step whose λ advanced by more than this times max_lambda_step is retried shorter.
constexpr double kLambdaStepSlack = 1.25;

double angle_between(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {  // unit vectors
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

std::string str(double v) {
  std::ostringstream s;
  s.precision(8);
  s << v;
  return s.str();
}

// The corrector's n+1 equations in the scaled unknowns y = (x / x_scale, λ / lambda_scale):
//   F(y) = [R(x, λ); residual_scale · (tᵀ (y − y_prev) − dsigma)],
//   dF/dy = [dR/dx · x_scale, dR/dλ · lambda_scale; residual_scale · tᵀ].
// The parameter argument of evaluate() is unused. Keeps the last Jacobian it computed so that the
// tangent at a converged point costs no extra evaluation.
class ArcLengthSystem final : public ParametrizedSystem {
 public:
  ArcLengthSystem(const ParametrizedSystem& sys, double x_scale, double lambda_scale)
      : sys_(sys), n_(sys.size()), x_scale_(x_scale), lambda_scale_(lambda_scale) {}

  void set_step(const Eigen::VectorXd& y_prev, const Eigen::VectorXd& t, double dsigma) {
    y_prev_ = y_prev;
    t_ = t;
    dsigma_ = dsigma;
  }

  int size() const override { return n_ + 1; }
  double residual_scale() const override { return sys_.residual_scale(); }
  // The corrector's convergence test: the system's scale at the last converged point's λ.
  double residual_scale_at(double /*unused*/) const override {
    return y_prev_.size() == n_ + 1 ? sys_.residual_scale_at(lambda_scale_ * y_prev_(n_))
                                    : sys_.residual_scale();
  }

  void evaluate(const Eigen::VectorXd& y, double /*unused*/, Eigen::VectorXd& F,
                Eigen::MatrixXd* dF_dy, Eigen::VectorXd* /*unused*/) const override {
    const double scale = sys_.residual_scale();
    x_ = x_scale_ * y.head(n_);
    Eigen::VectorXd R(n_);
    sys_.evaluate(x_, lambda_scale_ * y(n_), R, dF_dy ? &J_ : nullptr,
                  dF_dy ? &dR_dlambda_ : nullptr);
    STICKSLIP_VERIFY(R.size() == n_ && (!dF_dy || (J_.rows() == n_ && J_.cols() == n_ &&
                                                   dR_dlambda_.size() == n_)),
                     "ParametrizedSystem::evaluate must fill R, dR/dx and dR/dlambda (sizes n, "
                     "n x n, n) when asked for them");
    F.resize(n_ + 1);
    F.head(n_) = R;
    F(n_) = scale * (t_.dot(y - y_prev_) - dsigma_);
    if (dF_dy) {
      dF_dy->resize(n_ + 1, n_ + 1);
      dF_dy->topLeftCorner(n_, n_) = x_scale_ * J_;
      dF_dy->col(n_).head(n_) = lambda_scale_ * dR_dlambda_;
      dF_dy->row(n_) = scale * t_.transpose();
      cached_y_ = y;
      cached_dR_dy_ = dF_dy->topRows(n_);
    }
  }

  // dR/dy (n x (n+1)) at y, from the cache when the last Jacobian was computed at y.
  const Eigen::MatrixXd& dR_dy(const Eigen::VectorXd& y) const {
    if (cached_y_.size() != y.size() || cached_y_ != y) {
      Eigen::MatrixXd J;
      Eigen::VectorXd F;
      evaluate(y, 0.0, F, &J, nullptr);
    }
    return cached_dR_dy_;
  }

 private:
  const ParametrizedSystem& sys_;
  int n_;
  double x_scale_, lambda_scale_;
  Eigen::VectorXd y_prev_, t_;
  double dsigma_ = 0;
  mutable Eigen::VectorXd x_, dR_dlambda_, cached_y_;
  mutable Eigen::MatrixXd J_, cached_dR_dy_;
};

// Unit tangent t with [dR/dy; bᵀ] t = [0; 1], or nothing if the bordered matrix is singular or the
// result is not finite. bᵀ t = 1 / ||t_raw|| > 0 keeps the orientation of b.
std::optional<Eigen::VectorXd> tangent(const Eigen::MatrixXd& dR_dy, const Eigen::VectorXd& b,
                                       double min_rcond) {
  const Eigen::Index n1 = b.size();
  Eigen::MatrixXd B(n1, n1);
  // Row-scale the border to the size of dR/dy so that rcond measures geometry, not units.
  const double row_scale = std::max(dR_dy.cwiseAbs().maxCoeff(), 1e-300);
  B.topRows(n1 - 1) = dR_dy;
  B.row(n1 - 1) = row_scale * b.transpose();
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(B);
  if (!(lu.rcond() >= min_rcond)) return std::nullopt;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n1);
  rhs(n1 - 1) = row_scale;
  Eigen::VectorXd t = lu.solve(rhs);
  const double norm = t.norm();
  if (!std::isfinite(norm) || norm == 0) return std::nullopt;
  return Eigen::VectorXd(t / norm);
}

}  // namespace

void validate(const ArcLengthOptions& o) {
  const std::string p = "ArcLengthOptions.";
  require(std::isfinite(o.lambda_start), p + "lambda_start", str(o.lambda_start), "must be finite");
  require(std::isfinite(o.lambda_end) && o.lambda_end != o.lambda_start, p + "lambda_end",
          str(o.lambda_end), "must be finite and differ from lambda_start");
  require(std::isfinite(o.min_step) && o.min_step > 0, p + "min_step", str(o.min_step),
          "must be finite and > 0");
  require(std::isfinite(o.max_step) && o.max_step >= o.min_step, p + "max_step", str(o.max_step),
          "must be finite and >= min_step");
  require(o.initial_step >= o.min_step && o.initial_step <= o.max_step, p + "initial_step",
          str(o.initial_step), "must be in [min_step, max_step]");
  require(o.max_points >= 2, p + "max_points", std::to_string(o.max_points), "must be >= 2");
  require(o.target_newton_iterations >= 1, p + "target_newton_iterations",
          std::to_string(o.target_newton_iterations), "must be >= 1");
  validate(o.newton, p + "newton.");
  require(std::isfinite(o.x_scale) && o.x_scale >= 0, p + "x_scale", str(o.x_scale),
          "must be finite and >= 0 (0 = automatic)");
  require(std::isfinite(o.lambda_scale) && o.lambda_scale >= 0, p + "lambda_scale",
          str(o.lambda_scale), "must be finite and >= 0 (0 = automatic)");
  require(o.max_turn_angle > 0 && o.max_turn_angle < std::numbers::pi, p + "max_turn_angle",
          str(o.max_turn_angle), "must be in (0, pi)");
  require(std::isfinite(o.step_growth) && o.step_growth >= 1, p + "step_growth", str(o.step_growth),
          "must be finite and >= 1");
  require(o.target_turn_angle >= 0 && o.target_turn_angle < o.max_turn_angle,
          p + "target_turn_angle", str(o.target_turn_angle), "must be in [0, max_turn_angle)");
  require(std::isfinite(o.max_lambda_step) && o.max_lambda_step >= 0, p + "max_lambda_step",
          str(o.max_lambda_step), "must be finite and >= 0 (0 = no bound)");
  require(std::isfinite(o.max_correction) && o.max_correction > 0, p + "max_correction",
          str(o.max_correction), "must be finite and > 0");
  const bool behind =
      (o.lambda_end - o.lambda_start) * (o.lambda_return_limit - o.lambda_start) <= 0;
  require(std::isnan(o.lambda_return_limit) || (std::isfinite(o.lambda_return_limit) && behind),
          p + "lambda_return_limit", str(o.lambda_return_limit),
          "must be NaN (= lambda_start) or finite and not on the lambda_end side of lambda_start");
}

ContinuationResult arclength_continuation(const ParametrizedSystem& sys, const Eigen::VectorXd& x0,
                                          const ArcLengthOptions& options) {
  validate(options);
  const int n = sys.size();
  if (x0.size() != n) {
    throw InvalidInput("arclength_continuation: x0 has size " + std::to_string(x0.size()) +
                       " but the system has size " + std::to_string(n));
  }
  const double lambda_start = options.lambda_start, lambda_end = options.lambda_end;
  const double direction = lambda_end > lambda_start ? 1.0 : -1.0;
  const double return_limit =
      std::isnan(options.lambda_return_limit) ? lambda_start : options.lambda_return_limit;

  ContinuationResult result;
  auto push = [&](ContinuationPoint p) {
    const bool converged = p.newton.converged();
    const double lambda = p.lambda;
    result.points.push_back(std::move(p));
    if (options.on_point) {
      const double fraction =
          std::clamp((lambda - lambda_start) / (lambda_end - lambda_start), 0.0, 1.0);
      options.on_point({static_cast<int>(result.points.size()), lambda, fraction, converged,
                        &result.points.back().x});
    }
  };
  auto stop = [&](bool completed, const std::string& why) {
    result.completed = completed;
    std::ostringstream m;
    m << why << " (" << result.points.size() << " points)";
    result.message = m.str();
    return result;
  };

  // 1. First point.
  {
    ContinuationPoint first;
    first.lambda = lambda_start;
    first.x = x0;
    first.newton = solve_newton(sys, lambda_start, first.x, options.newton);
    push(first);
    if (!first.newton.converged()) {
      return stop(false, "no solution at lambda_start: " + first.newton.message);
    }
  }
  const Eigen::VectorXd x_first = result.points.front().x;
  const double x_scale =
      options.x_scale > 0 ? options.x_scale : (x_first.norm() > 0 ? x_first.norm() : 1.0);
  const double lambda_scale =
      options.lambda_scale > 0 ? options.lambda_scale : std::abs(lambda_end - lambda_start);

  result.x_scale = x_scale;
  result.lambda_scale = lambda_scale;
  ArcLengthSystem augmented(sys, x_scale, lambda_scale);
  Eigen::VectorXd y(n + 1);
  y << x_first / x_scale, lambda_start / lambda_scale;

  // 2. Tangent at the first point, oriented towards lambda_end.
  Eigen::VectorXd t;
  {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 1);
    b(n) = direction;
    augmented.set_step(y, b, 0.0);  // only dR/dy is used here
    auto t0 = tangent(augmented.dR_dy(y), b, options.newton.min_rcond);
    if (!t0) return stop(false, "dR/dx is singular at the first point: no tangent");
    t = *t0;
    result.points.front().tangent = t;
  }

  // Solution at exactly lambda_target from a guess interpolated between the last point (y) and a
  // point beyond it (y_new).
  auto clip_onto = [&](double lambda_target, const Eigen::VectorXd& y_new) {
    const double l0 = y(n) * lambda_scale, l1 = y_new(n) * lambda_scale;
    const double w = (lambda_target - l0) / (l1 - l0);
    ContinuationPoint p;
    p.lambda = lambda_target;
    p.x = x_scale * ((1 - w) * y.head(n) + w * y_new.head(n));
    p.newton = solve_newton(sys, lambda_target, p.x, options.newton);
    return p;
  };

  double step = options.initial_step;
  std::string last_failure;
  // The last attempt from y, if a guard (turn or correction) rejected it: its tangent and its
  // correction relative to the step.
  struct GuardRejection {
    Eigen::VectorXd t;
    double correction = 0;
  };
  std::optional<GuardRejection> rejected;
  while (static_cast<int>(result.points.size()) < options.max_points) {
    // 3. Predictor and corrector.
    const double dsigma = step / lambda_scale;
    augmented.set_step(y, t, dsigma);
    const Eigen::VectorXd y_predicted = y + dsigma * t;
    Eigen::VectorXd y_new = y_predicted;
    NewtonOptions corrector = options.newton;
    corrector.trial_jacobian = true;  // the tangent at the new point uses its dR/dy
    NewtonSummary summary = solve_newton(augmented, 0.0, y_new, corrector);

    // 4. Accept or reject.
    std::optional<Eigen::VectorXd> t_new;
    std::optional<GuardRejection> rejection;
    double shrink = 0.5;  // the step's factor if it is rejected
    if (summary.converged()) {
      const double correction = (y_new - y_predicted).norm() / dsigma;
      if (t_new = tangent(augmented.dR_dy(y_new), t, options.newton.min_rcond); !t_new) {
        last_failure = "singular bordered Jacobian at the corrected point";
      } else if (const double turn = angle_between(*t_new, t);
                 correction > options.max_correction || turn > options.max_turn_angle) {
        const bool corner = rejected && correction <= rejected->correction &&
                            angle_between(*t_new, rejected->t) <= kCornerTangentAgreement * turn;
        if (!corner) {
          last_failure = correction > options.max_correction
                             ? "the corrector moved farther than the step"
                             : "tangent turned by " + str(turn) + " rad > max_turn_angle";
          rejection = GuardRejection{std::move(*t_new), correction};
          t_new.reset();
        }
      }
      if (t_new && options.max_lambda_step > 0) {
        // The step was sized with the previous tangent's slope; where the curve bends towards λ
        // (leaving a resonance's flank) λ can advance further: retry with the step scaled down.
        const double advance = std::abs(y_new(n) - y(n)) * lambda_scale;
        if (advance > kLambdaStepSlack * options.max_lambda_step) {
          last_failure = "lambda advanced by " + str(advance) + " > max_lambda_step";
          shrink = std::max(0.1, options.max_lambda_step / advance);
          t_new.reset();
        }
      }
    } else {  // the corrector's lambda is an unknown: say where it started, not its argument
      last_failure = std::string("corrector from lambda = ") + str(y_predicted(n) * lambda_scale) +
                     ": " + to_string(summary.termination) + " after " +
                     std::to_string(summary.iterations) + " iterations";
    }
    if (!t_new) {
      rejected = std::move(rejection);
      step *= shrink;
      if (step < options.min_step) {
        return stop(false, "step below min_step = " + str(options.min_step) + " after lambda = " +
                               str(y(n) * lambda_scale) + "; last failure: " + last_failure);
      }
      continue;
    }

    // 5. Range checks.
    const double lambda_new = y_new(n) * lambda_scale;
    if (direction * (lambda_new - lambda_end) > 0) {
      ContinuationPoint p = clip_onto(lambda_end, y_new);
      if (p.newton.converged()) {
        push(std::move(p));
        return stop(true, "reached lambda_end");
      }
      return stop(true, "reached lambda_end; the solution at exactly lambda_end failed (" +
                            p.newton.message + "), the last point is before it");
    }
    if (direction * (lambda_new - return_limit) < 0) {
      ContinuationPoint p = clip_onto(return_limit, y_new);
      if (p.newton.converged()) push(std::move(p));
      return stop(false, std::isnan(options.lambda_return_limit)
                             ? "the branch turned back past lambda_start"
                             : "the branch turned back past lambda_return_limit");
    }

    ContinuationPoint p;
    p.lambda = lambda_new;
    p.x = x_scale * y_new.head(n);
    const int iterations = summary.iterations;
    p.newton = std::move(summary);
    p.tangent = *t_new;
    push(std::move(p));
    const double turn = angle_between(*t_new, t);
    y = y_new;
    t = *t_new;
    rejected.reset();
    double factor = 1;
    if (iterations < options.target_newton_iterations) {
      factor = options.step_growth;
    } else if (iterations > options.target_newton_iterations) {
      factor = kStepShrink;
    }
    if (options.target_turn_angle > 0) {
      const double by_turn =
          turn > 0 ? options.target_turn_angle / turn : std::numeric_limits<double>::infinity();
      factor = std::min(factor, std::clamp(by_turn, kStepShrink, options.step_growth));
    }
    step = std::clamp(step * factor, options.min_step, options.max_step);
    if (options.max_lambda_step > 0 && std::abs(t(n)) > 0) {
      // t is in y: Δλ = step · t_λ (lambda_scale cancels, see "Scaling").
      step = std::max(std::min(step, options.max_lambda_step / std::abs(t(n))), options.min_step);
    }
  }
  return stop(false, "max_points reached at lambda = " + str(y(n) * lambda_scale));
}

void validate(const ArcBisectionOptions& o) {
  const std::string p = "ArcBisectionOptions.";
  require(std::isfinite(o.tolerance) && o.tolerance > 0, p + "tolerance", str(o.tolerance),
          "must be finite and > 0");
  require(o.max_bisections >= 0, p + "max_bisections", std::to_string(o.max_bisections),
          "must be >= 0");
  require(std::isfinite(o.x_scale) && o.x_scale > 0, p + "x_scale", str(o.x_scale),
          "must be finite and > 0");
  require(std::isfinite(o.lambda_scale) && o.lambda_scale > 0, p + "lambda_scale",
          str(o.lambda_scale), "must be finite and > 0");
  validate(o.newton, p + "newton.");
}

ArcBisectionResult bisect_on_arc(const ParametrizedSystem& sys, const ContinuationPoint& a,
                                 double g_a, const ContinuationPoint& b, double g_b,
                                 const CurveTestFunction& g, const ArcBisectionOptions& options) {
  validate(options);
  const int n = sys.size();
  if (a.x.size() != n || b.x.size() != n) {
    throw InvalidInput("bisect_on_arc: the end points must have size " + std::to_string(n));
  }
  if (!(g_a * g_b < 0)) {
    throw InvalidInput("bisect_on_arc: g must change sign between the end points (g_a = " +
                       str(g_a) + ", g_b = " + str(g_b) + ")");
  }
  const double xs = options.x_scale, ls = options.lambda_scale;
  const auto scaled = [&](const ContinuationPoint& p) {
    Eigen::VectorXd y(n + 1);
    y << p.x / xs, p.lambda / ls;
    return y;
  };
  const Eigen::VectorXd ya = scaled(a), yb = scaled(b);
  const double chord = (yb - ya).norm();
  ArcBisectionResult result;
  if (!(chord > 0)) {
    result.message = "the end points coincide";
    return result;
  }
  const Eigen::VectorXd e = (yb - ya) / chord;
  ArcLengthSystem augmented(sys, xs, ls);
  // The curve's point on the plane eᵀ(y − y_a) = s · chord, from the guess y, with its tangent
  // (oriented along e); false when the corrector or the tangent fails.
  const auto solve_at = [&](double s, Eigen::VectorXd y, ContinuationPoint& out) {
    augmented.set_step(ya, e, s * chord);
    NewtonOptions corrector = options.newton;
    corrector.trial_jacobian = true;  // the tangent uses the solution's dR/dy
    out.newton = solve_newton(augmented, 0.0, y, corrector);
    ++result.solves;
    if (!out.newton.converged()) return false;
    auto t = tangent(augmented.dR_dy(y), e, options.newton.min_rcond);
    if (!t) return false;
    out.lambda = y(n) * ls;
    out.x = xs * y.head(n);
    out.tangent = std::move(*t);
    return true;
  };
  // Bracket [s_lo, s_hi] along the chord, g of opposite signs at its ends.
  double s_lo = 0, s_hi = 1, g_lo = g_a, g_hi = g_b;
  Eigen::VectorXd y_lo = ya, y_hi = yb;
  const auto bracket = [&] { return (y_hi - y_lo).norm() * ls; };
  int bisections = 0;
  while (bracket() > options.tolerance && bisections < options.max_bisections) {
    const double s = 0.5 * (s_lo + s_hi);
    ContinuationPoint mid;
    if (!solve_at(s, 0.5 * (y_lo + y_hi), mid)) {
      result.point = mid;
      result.bracket = bracket();
      result.message = "the corrector failed inside the bracket at lambda = " +
                       str(0.5 * (y_lo(n) + y_hi(n)) * ls) + ": " + mid.newton.message;
      return result;
    }
    ++bisections;
    const double gm = g(mid);
    if (!std::isfinite(gm)) {
      result.point = mid;
      result.bracket = bracket();
      result.message = "the test function is not defined at lambda = " + str(mid.lambda);
      return result;
    }
    const Eigen::VectorXd ym = scaled(mid);
    if (gm == 0) {  // an exact zero: the bracket shrinks to the point
      s_lo = s_hi = s;
      y_lo = y_hi = ym;
      g_lo = g_hi = 0;
      break;
    }
    if ((gm < 0) == (g_lo < 0)) {
      s_lo = s, y_lo = ym, g_lo = gm;
    } else {
      s_hi = s, y_hi = ym, g_hi = gm;
    }
  }
  result.bracket = bracket();
  // The estimate: the zero of g interpolated linearly in the bracket, solved on the curve.
  const double w = g_lo == g_hi ? 0.5 : g_lo / (g_lo - g_hi);
  const double s = s_lo + w * (s_hi - s_lo);
  ContinuationPoint estimate;
  if (!solve_at(s, (1 - w) * y_lo + w * y_hi, estimate)) {
    result.point = estimate;
    result.message = "the corrector failed at the interpolated zero: " + estimate.newton.message;
    return result;
  }
  result.point = std::move(estimate);
  result.g = g(result.point);
  result.located = result.bracket <= options.tolerance;
  result.message = result.located
                       ? "located after " + std::to_string(bisections) + " bisections"
                       : "max_bisections reached with a bracket of " + str(result.bracket);
  return result;
}

}  // namespace stickslip
