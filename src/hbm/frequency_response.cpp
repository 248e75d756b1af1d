#include "hbm/frequency_response.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"

namespace stickslip {

namespace {

// The complex harmonics of the contact displacements (unknowns x) and forces (rows × output
// harmonics), harmonic 0 from the frozen static state when the unknowns have none (uncoupled).
struct ContactHarmonics {
  Eigen::MatrixXcd u, f;
};
ContactHarmonics contact_harmonics(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                                   const Eigen::VectorXd& forces) {
  const bool frozen = !system.unknown_harmonics().has_static();
  return {system.to_complex(x, frozen ? system.static_displacement() : Eigen::VectorXd()),
          system.to_complex(forces, frozen ? system.static_force() : Eigen::VectorXd())};
}

// The balance at a fixed Ω with the dynamic excitation (harmonics ≥ 1) scaled by λ ∈ (0, 1]:
//   R_λ(x) = R(x, Ω) + (1 − λ) u_lin,dyn(Ω),  dR_λ/dx = dR/dx,  dR_λ/dλ = −u_lin,dyn(Ω).
class ExcitationRamp final : public ParametrizedSystem {
 public:
  ExcitationRamp(const HarmonicBalanceSystem& system, double omega)
      : system_(system), omega_(omega), ulin_dyn_(Eigen::VectorXd::Zero(system.size())) {
    const HarmonicSet& set = system.unknown_harmonics();
    const int nc = set.coefficient_count();
    for (int pos = 0; pos < set.size(); ++pos) {
      const int k = set.harmonics()[pos], o = set.offset(pos);
      if (k == 0) continue;
      const Eigen::VectorXcd ul = system.linear_contact_response(k, omega);
      for (int r = 0; r < system.contact_rows(); ++r) {
        ulin_dyn_[r * nc + o] = ul[r].real();
        ulin_dyn_[r * nc + o + 1] = -ul[r].imag();
      }
    }
  }
  int size() const override { return system_.size(); }
  double residual_scale() const override { return system_.residual_scale_at(omega_); }
  double residual_scale_at(double /*lambda*/) const override {
    return system_.residual_scale_at(omega_);
  }
  void evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& R, Eigen::MatrixXd* dR_dx,
                Eigen::VectorXd* dR_dlambda) const override {
    system_.evaluate(x, omega_, R, dR_dx, nullptr);
    R += (1.0 - lambda) * ulin_dyn_;
    if (dR_dlambda) *dR_dlambda = -ulin_dyn_;
  }

 private:
  const HarmonicBalanceSystem& system_;
  double omega_;
  Eigen::VectorXd ulin_dyn_;
};

// static: uncoupled: each pair's cycle-mean force against its frozen static force (see
// kStaticMismatchThreshold in the header). One extra march per pair without derivatives.
void check_static_state(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                        FrequencyPoint& point) {
  const Eigen::VectorXd& f0 = system.static_force();
  for (size_t p = 0; p < point.pairs.size(); ++p) {
    PairResponse& out = point.pairs[p];
    const int m = system.pairs()[p].element->dimension(), r = system.pair_row(static_cast<int>(p));
    const AftSamples cycle =
        out.history.f.size() > 0 ? out.history : system.pair_cycle(x, static_cast<int>(p));
    out.cycle_mean_force = cycle.f.rowwise().mean();
    const Eigen::VectorXd frozen = f0.segment(r, m);
    const double scale = std::max(frozen.norm(), cycle.f.colwise().norm().maxCoeff());
    out.static_mismatch = scale > 0 ? (out.cycle_mean_force - frozen).norm() / scale : 0.0;
    if (out.static_mismatch > point.static_mismatch || point.static_worst_pair < 0) {
      point.static_mismatch = out.static_mismatch;
      point.static_worst_pair = static_cast<int>(p);
    }
    if (out.static_mismatch > kStaticMismatchThreshold || separates_in_part(out.cycle)) {
      point.static_warning = true;
    }
  }
}

// The arc-length fallback of a stepped sweep (and of the first point's ramp) works on the dense
// dR/dx: for a system that solves its Newton steps structurally (a large one) it is off, so that a
// point that fails costs a few structured Newton solves, not dense Jacobians of its full size.
SteppedSweepOptions with_fallback_for(const HarmonicBalanceSystem& system, SteppedSweepOptions o) {
  if (system.has_structured_jacobian()) o.jump_max_points = 0;
  return o;
}

// Solution at the first frequency. The linear guess is tried first; if Newton fails from it (the
// stuck linear response can be far from a slipping solution near resonance: Newton then wanders
// among the stick/slip pieces of R), the harmonic excitation is ramped up at that frequency: from
// the largest fraction λ0 = 2^-j of it at which the scaled stuck guess is still stuck in every
// pair (there it is the exact solution), by factors of kRampFactor up to λ = 1 (stepped sweep in
// λ with its step halving). Returns the point at Ω = omega with the Newton solve that gave it (the
// ramp's last); on failure x is the plain guess and newton the failed solve from it.
ContinuationPoint first_solution(const HarmonicBalanceSystem& system, double omega, bool stuck,
                                 const NewtonOptions& newton) {
  const Eigen::VectorXd guess = system.linear_guess(omega, stuck);
  ContinuationPoint point;
  point.lambda = omega;
  point.x = guess;
  point.newton = solve_newton(system, omega, point.x, newton);
  if (point.newton.converged()) return point;
  constexpr double kRampFactor = 1.1;  // load increment per ramp step: 10 %
  constexpr int kMaxHalvings = 30;     // λ0 >= 2^-30
  const HarmonicSet& set = system.unknown_harmonics();
  const int nc = set.coefficient_count();
  auto scaled = [&](double lambda) {  // the static part of the guess, λ times its dynamic part
    Eigen::VectorXd y = guess;
    for (int pos = 0; pos < set.size(); ++pos) {
      if (set.harmonics()[pos] == 0) continue;
      for (int r = 0; r < system.contact_rows(); ++r) {
        y[r * nc + set.offset(pos)] *= lambda;
        y[r * nc + set.offset(pos) + 1] *= lambda;
      }
    }
    return y;
  };
  auto all_stuck = [&](double lambda) {
    Eigen::VectorXd forces;
    std::vector<CycleStatistics> stats;
    system.contact_forces(scaled(lambda), forces, &stats);
    return std::all_of(stats.begin(), stats.end(), [](const CycleStatistics& c) {
      return c.slip_fraction == 0 && c.separation_fraction == 0;
    });
  };
  double lambda0 = 1.0;
  for (int i = 0; i < kMaxHalvings && !all_stuck(lambda0); ++i) lambda0 *= 0.5;
  std::vector<double> lambdas{lambda0};
  while (lambdas.back() < 1.0) lambdas.push_back(std::min(1.0, lambdas.back() * kRampFactor));
  SteppedSweepOptions options;  // default step halving and arc-length fallback, in λ
  options.newton = newton;
  options = with_fallback_for(system, options);
  const ExcitationRamp ramp(system, omega);
  ContinuationResult r = stepped_sweep(ramp, scaled(lambda0), lambdas, options);
  if (r.points.back().newton.converged()) {
    point.x = std::move(r.points.back().x);
    point.newton = std::move(r.points.back().newton);
  } else {
    point.x = guess;
  }
  return point;
}

// Second chance for the points a stepped sweep could not solve (frequency_response.h). Near a fold
// of a strongly non-smooth response (heavy lift-off: every sample that switches between contact
// and separation puts a kink into R, and the solution curve has corners there) the sweep's branch
// ends, Newton stalls at a local minimum of ||R||, and neither step halving nor the arc-length
// fallback reaches the other branch. Each run of failed points is swept again backwards from the
// converged point after it (the branch a downward sweep follows), then, in a second pass,
// backwards again and forwards from the converged point before it (a point recovered by the first
// pass can start its neighbour); points still failing are solved from scratch like the first
// point. Points keep their order. The arc-length fallback (options.jump_max_points) is used in
// the first pass only: at a point that nothing solves it is expensive (arclength_continuation
// crosses corners instead of stopping at the first), and in the second pass it changed no result
// (docs/performance.md, "Heavy lift-off": without it the same 10 of 52 488 points fail, and the
// retries cost 120 instead of 175 G instructions). Returns how many were recovered. Without any
// converged point there is nothing to start from (and the first point's ramp has failed):
// nothing is tried.
int retry_failed_points(const HarmonicBalanceSystem& system, std::span<const double> omegas,
                        SteppedSweepOptions options, bool stuck, ContinuationResult& result) {
  std::vector<ContinuationPoint>& points = result.points;
  const int n = static_cast<int>(points.size());
  auto ok = [&](int i) { return points[i].newton.converged(); };
  if (std::none_of(points.begin(), points.end(),
                   [](const ContinuationPoint& p) { return p.newton.converged(); })) {
    return 0;
  }
  options.on_point = nullptr;  // the progress of the sweep has been reported already
  int recovered = 0;
  auto take = [&](int k, ContinuationPoint&& p) {
    if (ok(k) || !p.newton.converged()) return;
    points[k] = std::move(p);
    ++recovered;
  };
  // Stepped sweep from the converged point `from` to `to` (inclusive).
  auto sweep_from = [&](int from, int to) {
    const int dir = to > from ? 1 : -1;
    std::vector<double> lambdas;
    for (int k = from; k != to + dir; k += dir) lambdas.push_back(omegas[k]);
    ContinuationResult r =
        stepped_sweep(system, points[from].x, std::span<const double>(lambdas), options);
    for (size_t q = 1; q < r.points.size(); ++q) {
      take(from + dir * static_cast<int>(q), std::move(r.points[q]));
    }
  };
  for (int pass = 0; pass < 2; ++pass) {
    if (pass > 0) options.jump_max_points = 0;  // fallback in the first pass only
    for (int i = 0; i < n; ++i) {
      if (ok(i)) continue;
      int j = i;  // [i, j]: a run of failed points
      while (j + 1 < n && !ok(j + 1)) ++j;
      if (j + 1 < n) sweep_from(j + 1, i);
      if (pass > 0 && i > 0) {  // forwards from the point before what is left of the run
        int k = i;
        while (k <= j && ok(k)) ++k;
        if (k <= j) sweep_from(k - 1, j);
      }
      i = j;
    }
  }
  for (int k = 1; k < n; ++k) {  // (the first point's ramp has been tried)
    if (!ok(k)) take(k, first_solution(system, omegas[k], stuck, options.newton));
  }

  constexpr int kListed = 10;  // keep the message one readable line
  int failed = 0;
  std::ostringstream list;
  for (int i = 0; i < n; ++i) {
    if (ok(i)) continue;
    if (failed < kListed) list << " " << points[i].lambda;
    ++failed;
  }
  std::ostringstream m;
  m << (n - failed) << " of " << n << " points converged";
  if (failed > 0) m << "; not converged at lambda =" << list.str();
  if (failed > kListed) m << " ... (" << failed - kListed << " more)";
  m << "; " << recovered << " of them recovered by sweeping again from a converged neighbour";
  for (int i = 0; i < n; ++i) {  // the first failure's reason
    if (ok(i)) continue;
    m << "; at lambda = " << points[i].lambda << ": ";
    if (points[i].failure.empty()) {
      m << "Newton: " << points[i].newton.message;
    } else {
      m << points[i].failure;
    }
    break;
  }
  result.completed = failed == 0;
  result.message = m.str();
  return recovered;
}

// A bisection on the continuation's curve (bisect_on_arc) with its scales and corrector; the
// tolerance relative to lambda_scale.
ArcBisectionOptions bisection_on(const ContinuationResult& curve, double relative_tolerance,
                                 int max_bisections, const FrequencyResponseOptions& options) {
  ArcBisectionOptions bisection;
  bisection.tolerance = relative_tolerance * curve.lambda_scale;
  bisection.max_bisections = max_bisections;
  bisection.x_scale = curve.x_scale;
  bisection.lambda_scale = curve.lambda_scale;
  bisection.newton = options.arclength.newton;
  return bisection;
}

// The bifurcations of an arc-length continuation (frequency_response.h), in the order of the curve.
std::vector<Bifurcation> locate_bifurcations(const HarmonicBalanceSystem& system,
                                             const ContinuationResult& curve,
                                             const std::vector<FrequencyPoint>& points,
                                             const FrequencyResponseOptions& options) {
  std::vector<Bifurcation> found;
  const int n = system.size();
  const ArcBisectionOptions bisection = bisection_on(curve, options.bifurcations.tolerance,
                                                     options.bifurcations.max_bisections, options);
  if (!(curve.x_scale > 0 && curve.lambda_scale > 0)) return found;  // only a first point
  const auto add = [&](BifurcationType type, int i, const ArcBisectionResult& r,
                       MultiplierKind kind) {
    Bifurcation b;
    b.type = type;
    b.after_point = i;
    b.located = r.located;
    b.bracket = r.bracket;
    b.message = r.message;
    const bool solved = r.point.x.size() == n && r.point.newton.converged();
    if (solved) {
      b.point = evaluate_point(system, r.point.x, r.point.lambda);
      b.point.converged = true;
      b.point.iterations = r.point.newton.iterations;
      b.point.residual_norm = r.point.newton.residual_norm;
      b.point.message = r.point.newton.message;
    } else {
      b.point = points[i];
      b.message += "; the point before is given";
    }
    if (options.stability && solved) {
      b.point.floquet = hill_stability(system, b.point.unknowns, b.point.omega, options.hill);
      b.point.stability_computed = true;
      b.multiplier = critical_multiplier(b.point.floquet, kind, b.point.omega);
    }
    found.push_back(std::move(b));
  };
  const auto fold_test = [n](const ContinuationPoint& p) { return p.tangent(n); };
  for (size_t i = 0; i + 1 < curve.points.size() && i + 1 < points.size(); ++i) {
    const ContinuationPoint &a = curve.points[i], &c = curve.points[i + 1];
    if (!a.newton.converged() || !c.newton.converged()) continue;
    const int at = static_cast<int>(i);
    bool fold = false;
    if (a.tangent.size() == n + 1 && c.tangent.size() == n + 1 && a.tangent(n) * c.tangent(n) < 0) {
      fold = true;
      add(BifurcationType::kFold, at,
          bisect_on_arc(system, a, a.tangent(n), c, c.tangent(n), fold_test, bisection),
          MultiplierKind::kPlusOne);
    }
    const FrequencyPoint &pa = points[i], &pc = points[i + 1];
    if (!options.stability || !pa.stability_computed || !pc.stability_computed) continue;
    for (const MultiplierKind kind :
         unit_circle_crossings(pa.floquet, pa.omega, pc.floquet, pc.omega, options.hill)) {
      if (kind == MultiplierKind::kPlusOne && fold) continue;  // the fold's own multiplier
      // The test function: the largest Re μ of this kind. When the kind is missing at one end
      // (a complex pair that met the real axis and crossed within one step), the largest Re μ
      // of all. Of opposite signs at the ends: a crossing, not a change of kind outside the
      // circle (a complex pair meeting on the real axis there) nor one within the stability
      // tolerance.
      double ga = largest_real_part(pa.floquet, kind, pa.omega);
      double gc = largest_real_part(pc.floquet, kind, pc.omega);
      const bool of_kind = std::isfinite(ga) && std::isfinite(gc);
      if (!of_kind) ga = pa.floquet.max_real_part, gc = pc.floquet.max_real_part;
      if (!(ga * gc < 0)) continue;
      const auto test = [&](const ContinuationPoint& p) {
        const FloquetSummary s = hill_stability(system, p.x, p.lambda, options.hill);
        return of_kind ? largest_real_part(s, kind, p.lambda) : s.max_real_part;
      };
      const BifurcationType type = kind == MultiplierKind::kPlusOne ? BifurcationType::kBranchPoint
                                   : kind == MultiplierKind::kMinusOne
                                       ? BifurcationType::kPeriodDoubling
                                       : BifurcationType::kNeimarkSacker;
      add(type, at, bisect_on_arc(system, a, ga, c, gc, test, bisection), kind);
    }
  }
  return found;
}

// A² = |X|² of master DOF `dof`, output column `column`, at (x, Ω) (as evaluate_point computes the
// master response).
double amplitude_squared(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                         double omega, int dof, int column) {
  Eigen::VectorXd forces;
  system.contact_forces(x, forces, nullptr);
  const ContactHarmonics c = contact_harmonics(system, x, forces);
  return std::norm(system.master_response(c.f, omega, &c.u)(dof, column));
}

// The response peaks of an arc-length continuation (frequency_response.h, PeakOptions).
std::vector<ResponsePeak> locate_peaks(const HarmonicBalanceSystem& system,
                                       const ContinuationResult& curve,
                                       const std::vector<FrequencyPoint>& points,
                                       const std::vector<int>& harmonics,
                                       const FrequencyResponseOptions& options) {
  std::vector<ResponsePeak> found;
  const int n = system.size();
  const auto first_dynamic =
      std::find_if(harmonics.begin(), harmonics.end(), [](int h) { return h != 0; });
  const int column =
      first_dynamic == harmonics.end() ? -1 : static_cast<int>(first_dynamic - harmonics.begin());
  const ArcBisectionOptions bisection =
      bisection_on(curve, options.peaks.tolerance, options.peaks.max_bisections, options);
  const int count = static_cast<int>(std::min(curve.points.size(), points.size()));
  const auto converged = [&](int i) {
    return i >= 0 && i < count && curve.points[i].newton.converged() &&
           curve.points[i].tangent.size() == n + 1;
  };
  for (const int dof : options.peaks.dofs) {
    ResponsePeak peak;
    peak.dof = dof;
    for (int i = 0; i < count && column >= 0; ++i) {
      if (!points[i].converged) continue;
      const double a = std::abs(points[i].master(dof, column));
      if (peak.sampled_point < 0 || a > peak.amplitude) {
        peak.sampled_point = i;
        peak.amplitude = a;
        peak.omega = points[i].omega;
      }
    }
    const int i = peak.sampled_point;
    if (i < 0 || !(curve.x_scale > 0 && curve.lambda_scale > 0)) {
      peak.message = "no converged point on the curve";
      found.push_back(std::move(peak));
      continue;
    }
    // g = dA²/dσ along the unit tangent t (scaled variables), by central differences with a
    // step h relative to the point's size in y: the truncation error O(h²) and the round-off
    // O(ε A² / h) are both far below the bisection's resolution.
    const auto g = [&](const ContinuationPoint& p) {
      const double ys = std::hypot(p.x.norm() / curve.x_scale, p.lambda / curve.lambda_scale);
      const double h = 1e-6 * std::max(1.0, ys);
      const Eigen::VectorXd dx = (h * curve.x_scale) * p.tangent.head(n);
      const double dl = h * curve.lambda_scale * p.tangent(n);
      return (amplitude_squared(system, p.x + dx, p.lambda + dl, dof, column) -
              amplitude_squared(system, p.x - dx, p.lambda - dl, dof, column)) /
             (2 * h);
    };
    if (!converged(i) || !converged(i - 1) || !converged(i + 1)) {
      peak.message = i == 0 || i + 1 >= count
                         ? "the largest amplitude is at an end of the curve: the peak may lie "
                           "outside the window"
                         : "a neighbour of the largest sampled amplitude did not converge";
      found.push_back(std::move(peak));
      continue;
    }
    // A still rises after point i: the maximum is between i and i + 1, else between i − 1 and i.
    const double g_i = g(curve.points[i]);
    const int lo = g_i > 0 ? i : i - 1;
    const double g_lo = g_i > 0 ? g_i : g(curve.points[i - 1]);
    const double g_hi = g_i > 0 ? g(curve.points[i + 1]) : g_i;
    if (!(g_lo > 0 && g_hi < 0)) {
      peak.message =
          "dA/ds does not change sign next to the largest sampled amplitude (a peak on a corner of "
          "the curve): the sampled maximum is given";
      found.push_back(std::move(peak));
      continue;
    }
    const ArcBisectionResult r =
        bisect_on_arc(system, curve.points[lo], g_lo, curve.points[lo + 1], g_hi, g, bisection);
    peak.bracket = r.bracket;
    peak.message = r.message;
    if (r.located) {
      const double a = std::sqrt(amplitude_squared(system, r.point.x, r.point.lambda, dof, column));
      if (a >= peak.amplitude) {  // never report less than a point the curve has
        peak.located = true;
        peak.amplitude = a;
        peak.omega = r.point.lambda;
      } else {
        peak.message += "; the located amplitude is below the sampled maximum: the latter is given";
      }
    }
    found.push_back(std::move(peak));
  }
  return found;
}

}  // namespace

const char* to_string(BifurcationType type) {
  switch (type) {
    case BifurcationType::kFold:
      return "fold";
    case BifurcationType::kBranchPoint:
      return "branch_point";
    case BifurcationType::kPeriodDoubling:
      return "period_doubling";
    case BifurcationType::kNeimarkSacker:
      return "neimark_sacker";
  }
  return "unknown";
}

void validate(const PeakOptions& o, int master_dofs) {
  for (size_t i = 0; i < o.dofs.size(); ++i) {
    require(o.dofs[i] >= 0 && o.dofs[i] < master_dofs,
            "PeakOptions.dofs[" + std::to_string(i) + "]", std::to_string(o.dofs[i]),
            "in [0, " + std::to_string(master_dofs) + ")");
  }
  require(std::isfinite(o.tolerance) && o.tolerance > 0, "PeakOptions.tolerance",
          std::to_string(o.tolerance), "finite and > 0");
  require(o.max_bisections >= 0, "PeakOptions.max_bisections", std::to_string(o.max_bisections),
          ">= 0");
}

void validate(const BifurcationOptions& o) {
  require(std::isfinite(o.tolerance) && o.tolerance > 0, "BifurcationOptions.tolerance",
          std::to_string(o.tolerance), "finite and > 0");
  require(o.max_bisections >= 0, "BifurcationOptions.max_bisections",
          std::to_string(o.max_bisections), ">= 0");
}

FrequencyPoint evaluate_point(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                              double omega, const std::vector<int>& history_pairs) {
  FrequencyPoint point;
  point.omega = omega;
  point.unknowns = x;
  point.residual_scale = system.residual_scale_at(omega);  // the operator at Ω is still cached
  Eigen::VectorXd forces;
  std::vector<CycleStatistics> stats;
  system.contact_forces(x, forces, &stats);  // usually the last residual's, kept by the system
  const bool frozen = !system.unknown_harmonics().has_static();
  const auto [u, f] = contact_harmonics(system, x, forces);
  point.master = system.master_response(f, omega, &u);
  point.pairs.resize(system.pairs().size());
  for (size_t p = 0; p < system.pairs().size(); ++p) {
    const ContactPair& pair = system.pairs()[p];
    const int m = pair.element->dimension(), r = system.pair_row(static_cast<int>(p));
    PairResponse& out = point.pairs[p];
    out.displacement_local = u.middleRows(r, m);
    out.force_local = f.middleRows(r, m);
    out.force_global = pair.frame.transpose().cast<std::complex<double>>() * out.force_local;
    out.cycle = stats[p];
  }
  for (int p : history_pairs) point.pairs[p].history = system.pair_cycle(x, p);
  if (frozen) check_static_state(system, x, point);
  return point;
}

FrequencyResponse frequency_response(const HarmonicBalanceSystem& system,
                                     const FrequencyResponseOptions& options) {
  const int npairs = static_cast<int>(system.pairs().size());
  for (size_t i = 0; i < options.history_pairs.size(); ++i) {
    require(options.history_pairs[i] >= 0 && options.history_pairs[i] < npairs,
            "FrequencyResponseOptions.history_pairs[" + std::to_string(i) + "]",
            std::to_string(options.history_pairs[i]), "in [0, " + std::to_string(npairs) + ")");
  }
  if (options.stability) validate(options.hill);
  validate(options.bifurcations);
  validate(options.peaks, system.master_dofs());
  require(system.size() > 0 || options.method == ContinuationMethod::kSteppedSweep,
          "FrequencyResponseOptions.method", "arc-length",
          "a stepped sweep when the system has no unknowns (no contact pairs: a linear response)");
  ContinuationResult result;
  const bool stuck = options.initial_guess == InitialGuess::kLinearStuck;
  // The outputs of each point are evaluated as soon as it is solved: the last residual evaluation
  // was then (usually) at its solution, whose contact forces the system still holds.
  std::vector<FrequencyPoint> outputs;
  auto evaluate_outputs = [&](const ProgressCallback& user) -> ProgressCallback {
    return [&, user](const ContinuationProgress& p) {
      if (p.x) outputs.push_back(evaluate_point(system, *p.x, p.lambda, options.history_pairs));
      if (user) user(p);
    };
  };
  if (options.method == ContinuationMethod::kSteppedSweep) {
    require(!options.omegas.empty(), "FrequencyResponseOptions.omegas", "[]", "not empty");
    const Eigen::VectorXd x0 =
        first_solution(system, options.omegas.front(), stuck, options.sweep.newton).x;
    SteppedSweepOptions sweep = with_fallback_for(system, options.sweep);
    sweep.on_point = evaluate_outputs(options.sweep.on_point);
    result = stepped_sweep(system, x0, std::span<const double>(options.omegas), sweep);
    if (!result.completed) {
      retry_failed_points(system, options.omegas, with_fallback_for(system, options.sweep), stuck,
                          result);
    }
    if (!result.completed && sweep.jump_max_points != options.sweep.jump_max_points) {
      result.message +=
          "; no arc-length fallback for a system this large (it needs the dense dR/dx)";
    }
  } else {
    validate(options.arclength);
    const Eigen::VectorXd x0 =
        first_solution(system, options.arclength.lambda_start, stuck, options.arclength.newton).x;
    ArcLengthOptions arclength = options.arclength;
    arclength.on_point = evaluate_outputs(options.arclength.on_point);
    result = arclength_continuation(system, x0, arclength);
  }
  FrequencyResponse response;
  response.harmonics = system.output_harmonics();
  response.completed = result.completed;
  response.message = result.message;
  if (!system.static_summary().converged()) {
    response.message =
        "static problem: " + system.static_summary().message + "; " + response.message;
  }
  for (size_t i = 0; i < result.points.size(); ++i) {
    const ContinuationPoint& c = result.points[i];
    const bool early = i < outputs.size() && outputs[i].omega == c.lambda &&
                       outputs[i].unknowns.size() == c.x.size() && outputs[i].unknowns == c.x;
    FrequencyPoint point = early ? std::move(outputs[i])
                                 : evaluate_point(system, c.x, c.lambda, options.history_pairs);
    point.converged = c.newton.converged();
    point.iterations = c.newton.iterations;
    point.residual_norm = c.newton.residual_norm;
    point.message = c.newton.message;
    if (options.stability && point.converged) {
      point.floquet = hill_stability(system, c.x, c.lambda, options.hill);
      point.stability_computed = true;
    }
    response.points.push_back(std::move(point));
  }
  if (options.method == ContinuationMethod::kArcLength && options.bifurcations.enabled) {
    response.bifurcations = locate_bifurcations(system, result, response.points, options);
  }
  if (options.method == ContinuationMethod::kArcLength && !options.peaks.dofs.empty()) {
    response.peaks = locate_peaks(system, result, response.points, response.harmonics, options);
  }
  return response;
}

}  // namespace stickslip
