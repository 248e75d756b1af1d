// Bifurcations along an arc-length continuation (hbm/frequency_response.h, issue 14 item 2),
// against independent references:
//   folds of the Duffing oscillator at H = 1 against the closed form of its single-harmonic
//     amplitude equation ((k − mΩ² + ¾ k3 a²)² + (cΩ)²) a² = F², whose folds are dΩ/da = 0;
//   period doubling of a Helmholtz–Duffing oscillator (the double-well Duffing about one of its
//     wells) in its principal parametric resonance, against the monodromy matrix of the
//     variational equation integrated in time here (RK4) along the located orbit;
//   the classification of multiplier crossings (Neimark–Sacker included: no forced 1-DOF case has
//     one, and none with a closed form or a time integration was within reach) on constructed
//     exponent sequences.
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "contact/springs.h"
#include "core/errors.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"
#include "hbm/hill_stability.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;

// Duffing: ẍ + c ẋ + k x + k3 x³ = F cos Ωt, m = 1 (the cubic spring as the element).
constexpr double kStiffness = 1.0, kDamping = 0.02, kCubic = 1.0, kForce = 0.03;

HarmonicBalanceSystem duffing(int harmonics) {
  LinearModel model;
  model.omega2 = VectorXd::Constant(1, kStiffness);
  model.Phi = MatrixXd::Constant(1, 1, 1.0);
  model.modal_damping = VectorXd::Constant(1, kDamping);
  ContactPair pair{.dofs_a = {0},
                   .dofs_b = {},
                   .frame = MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<CubicSpring>(CubicSpringParameters{.k3 = kCubic})};
  Excitation e;
  e.harmonics[1] = Eigen::VectorXcd::Constant(1, kForce);
  HarmonicBalanceOptions o;
  o.harmonics = harmonics;
  o.time_samples = 16;  // u³ at H = 1 has harmonics up to 3 < 8: the AFT is exact
  o.static_coupling = StaticCoupling::kCoupled;
  return HarmonicBalanceSystem(model, {pair}, e, o);
}

// The folds of the amplitude equation G(u, Ω) = ((p + ¾k3 u)² + c²Ω²) u − F² = 0, u = a²,
// p = k − Ω²: dΩ/da = 0 ⇔ ∂G/∂u = 0. With q = p + ¾k3 u the two equations
//   q² + c²Ω² = F²/u  and  q² + c²Ω² + (3/2) k3 u q = 0
// give q = −2F²/(3 k3 u²) and Ω² = k + ¾k3 u − q, leaving one equation in u:
//   h(u) = c² (k + ¾k3 u − q(u)) − F²/u + q(u)² = 0,
// whose roots are bracketed on a logarithmic grid and refined by bisection to round-off.
struct FoldReference {
  double omega, amplitude;
};
std::vector<FoldReference> duffing_folds() {
  const auto q = [](double u) { return -2 * kForce * kForce / (3 * kCubic * u * u); };
  const auto h = [&](double u) {
    return kDamping * kDamping * (kStiffness + 0.75 * kCubic * u - q(u)) - kForce * kForce / u +
           q(u) * q(u);
  };
  std::vector<FoldReference> folds;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    double a = std::pow(10.0, -4 + 5.0 * i / n), b = std::pow(10.0, -4 + 5.0 * (i + 1) / n);
    if (h(a) * h(b) >= 0) continue;
    for (int j = 0; j < 200; ++j) {
      const double m = 0.5 * (a + b);
      (h(a) * h(m) <= 0 ? b : a) = m;
    }
    const double u = 0.5 * (a + b);
    folds.push_back({std::sqrt(kStiffness + 0.75 * kCubic * u - q(u)), std::sqrt(u)});
  }
  return folds;
}

FrequencyResponseOptions continuation(double from, double to) {
  FrequencyResponseOptions r;
  r.method = ContinuationMethod::kArcLength;
  r.initial_guess = InitialGuess::kLinearFree;
  r.arclength.lambda_start = from;
  r.arclength.lambda_end = to;
  r.arclength.initial_step = 0.005;
  r.arclength.min_step = 1e-7;
  r.arclength.max_step = 0.02;
  r.arclength.x_scale = 1.0;
  r.arclength.newton.tolerance = 1e-12;
  return r;
}

TEST(Bifurcations, DuffingFoldsAtHarmonicOneMatchTheAmplitudeEquation) {
  const std::vector<FoldReference> reference = duffing_folds();
  ASSERT_EQ(reference.size(), 2u);  // Ω ≈ 1.079 (a ≈ 0.273) and 1.376 (a ≈ 1.090)
  const HarmonicBalanceSystem sys = duffing(1);
  for (const bool stability : {false, true}) {
    FrequencyResponseOptions r = continuation(0.5, 2.0);
    r.stability = stability;
    const FrequencyResponse fr = frequency_response(sys, r);
    ASSERT_TRUE(fr.completed) << fr.message;
    // Along increasing arc length the curve meets the upper fold (the peak) first.
    ASSERT_EQ(fr.bifurcations.size(), 2u) << "stability " << stability;
    // The bound of bisect_on_arc: |ΔΩ| <= bracket, |Δx| <= bracket · x_scale / lambda_scale
    // (x_scale = 1, lambda_scale = 1.5), plus the corrector's tolerance (1e-12 of the scale).
    const double tolerance = BifurcationOptions{}.tolerance * 1.5;
    double worst_omega = 0, worst_amplitude = 0;
    for (int i = 0; i < 2; ++i) {
      const Bifurcation& b = fr.bifurcations[i];
      const FoldReference& ref = reference[1 - i];
      EXPECT_EQ(b.type, BifurcationType::kFold);
      EXPECT_TRUE(b.located) << b.message;
      EXPECT_LE(b.bracket, tolerance);
      const double a = std::abs(b.point.master(0, 1));
      EXPECT_NEAR(b.point.omega, ref.omega, b.bracket + 1e-10) << "fold " << i;
      EXPECT_NEAR(a, ref.amplitude, b.bracket / 1.5 + 1e-10) << "fold " << i;
      worst_omega = std::max(worst_omega, std::abs(b.point.omega - ref.omega));
      worst_amplitude = std::max(worst_amplitude, std::abs(a - ref.amplitude));
      if (stability) {
        // At a fold one multiplier is +1; no branch point is reported for it.
        EXPECT_NEAR(b.multiplier.real(), 1.0, 1e-4) << "fold " << i;
        EXPECT_NEAR(b.multiplier.imag(), 0.0, 1e-4);
      } else {
        EXPECT_TRUE(std::isnan(b.multiplier.real()));
      }
    }
    std::ostringstream text;
    text << worst_omega << " rad/s, " << worst_amplitude;
    RecordProperty(stability ? "fold_error_with_stability" : "fold_error", text.str());
  }
}

// Helmholtz–Duffing: the double-well Duffing ẍ + δẋ − x + x³ = γ cos Ωt written about its well
// x = 1 (x = 1 + y): ÿ + δẏ + 2y + 3y² + y³ = γ cos Ωt. The forced period-1 orbit modulates the
// stiffness 2 + 6y + 3y²: near Ω = 2·√2 (principal parametric resonance of the well's mode) it
// loses stability by period doubling, a real multiplier through −1, and regains it further on.
// With δ = 0.1, γ = 0.4 a shooting computation (period map by RK4, Newton on its fixed point; run
// once while writing this test, not used by it) puts the multiplier −1 near Ω = 2.69 and 2.905.
constexpr double kWellStiffness = 2.0, kWellDamping = 0.1, kQuadratic = 3.0, kWellCubic = 1.0,
                 kWellForce = 0.4;

// f = k2 u² + k3 u³ (the linear part is in the modal stiffness).
class QuadraticCubicSpring final : public NonlinearElement {
 public:
  int dimension() const override { return 1; }
  std::string name() const override { return "quadratic_cubic_spring"; }
  CycleStatistics march(const MatrixXd& u, const MatrixXd* du_dp, MatrixXd& f,
                        MatrixXd* df_dp) const override {
    const int n = static_cast<int>(u.cols());
    f.resize(1, n);
    if (df_dp) df_dp->resize(n, du_dp->cols());
    for (int j = 0; j < n; ++j) {
      const double x = u(0, j);
      f(0, j) = kQuadratic * x * x + kWellCubic * x * x * x;
      if (df_dp) df_dp->row(j) = (2 * kQuadratic * x + 3 * kWellCubic * x * x) * du_dp->row(j);
    }
    CycleStatistics stats;
    stats.stick_fraction = 1.0;
    stats.periods = 1;
    return stats;
  }
};

HarmonicBalanceSystem well(int harmonics) {
  LinearModel model;
  model.omega2 = VectorXd::Constant(1, kWellStiffness);
  model.Phi = MatrixXd::Constant(1, 1, 1.0);
  model.modal_damping = VectorXd::Constant(1, kWellDamping);
  ContactPair pair{.dofs_a = {0},
                   .dofs_b = {},
                   .frame = MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<QuadraticCubicSpring>()};
  Excitation e;
  e.harmonics[1] = Eigen::VectorXcd::Constant(1, kWellForce);
  HarmonicBalanceOptions o;
  o.harmonics = harmonics;
  o.time_samples = 64;  // u³ up to harmonic 3H = 21 < 32: the AFT is exact
  o.static_coupling = StaticCoupling::kCoupled;
  return HarmonicBalanceSystem(model, {pair}, e, o);
}

// Floquet multipliers of the orbit y(t) (coefficients c over S) from the variational equation
// δÿ + δ δẏ + (2 + 6y + 3y²) δy = 0 integrated over one period (classical RK4).
Eigen::Vector2cd well_monodromy(const HarmonicSet& S, const VectorXd& c, double omega) {
  auto displacement = [&](double t) {
    double y = 0;
    for (int p = 0; p < S.size(); ++p) {
      const int k = S.harmonics()[p], o = S.offset(p);
      y += k == 0 ? c[o] : c[o] * std::cos(k * omega * t) + c[o + 1] * std::sin(k * omega * t);
    }
    return y;
  };
  auto rate = [&](double t, const Eigen::Matrix2d& P) {
    const double y = displacement(t);
    Eigen::Matrix2d A;
    A << 0, 1, -(kWellStiffness + 2 * kQuadratic * y + 3 * kWellCubic * y * y), -kWellDamping;
    return Eigen::Matrix2d(A * P);
  };
  const int steps = 4000;
  const double T = 2 * kPi / omega, h = T / steps;
  Eigen::Matrix2d P = Eigen::Matrix2d::Identity();
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    const Eigen::Matrix2d k1 = rate(t, P), k2 = rate(t + h / 2, P + h / 2 * k1),
                          k3 = rate(t + h / 2, P + h / 2 * k2), k4 = rate(t + h, P + h * k3);
    P += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return Eigen::EigenSolver<Eigen::Matrix2d>(P, false).eigenvalues();
}

// The multiplier of the monodromy matrix nearest −1.
std::complex<double> nearest_minus_one(const Eigen::Vector2cd& rho) {
  return std::abs(rho[0] + 1.0) < std::abs(rho[1] + 1.0) ? rho[0] : rho[1];
}

// The largest amplitude of the Duffing curve at H = 1 (PeakOptions): along the curve of the
// amplitude equation G(a², Ω) = 0 the amplitude is largest where ∂G/∂Ω = 0, i.e.
// q = k − Ω² + ¾k3 u = c²/2 (u = a²); with G = 0 this leaves ¾k3c² u² + c²(k − c²/4) u − F² = 0
// and Ω² = k + ¾k3 u − c²/2. The continuation's own points (curvature-controlled steps, as the
// program takes them) sample the peak more coarsely; the located maximum is on the curve.
TEST(ResponsePeaks, DuffingPeakAtHarmonicOneMatchesTheAmplitudeEquation) {
  const double c2 = kDamping * kDamping;
  const double qa = 0.75 * kCubic * c2, qb = c2 * (kStiffness - c2 / 4), qc = -kForce * kForce;
  const double u = (-qb + std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
  const double omega_peak = std::sqrt(kStiffness + 0.75 * kCubic * u - c2 / 2);
  const double a_peak = std::sqrt(u);
  ASSERT_NEAR(a_peak, 1.0906, 1e-3);  // just before the upper fold (Ω ≈ 1.376, a ≈ 1.090)
  const HarmonicBalanceSystem sys = duffing(1);
  FrequencyResponseOptions r = continuation(0.5, 2.0);
  r.arclength.max_step = 0.2;
  r.arclength.target_turn_angle = 0.1;  // the program's curvature control (case_model.cpp)
  r.arclength.max_lambda_step = 0.075;
  r.peaks.dofs = {0};
  const FrequencyResponse fr = frequency_response(sys, r);
  ASSERT_TRUE(fr.completed) << fr.message;
  ASSERT_EQ(fr.peaks.size(), 1u);
  const ResponsePeak& peak = fr.peaks[0];
  ASSERT_TRUE(peak.located) << peak.message;
  ASSERT_GE(peak.sampled_point, 1);
  const FrequencyPoint& sampled = fr.points[peak.sampled_point];
  const double sampled_error = a_peak - std::abs(sampled.master(0, 1));
  // The bisection's bracket is 1e-8 of the range (1.5): Ω within it; A is flat at its maximum,
  // so the amplitude is exact to the square of the bracket (and the corrector's 1e-12).
  EXPECT_LE(peak.bracket, 1e-8 * 1.5 * (1 + 1e-12));
  EXPECT_NEAR(peak.omega, omega_peak, peak.bracket + 1e-10);
  EXPECT_NEAR(peak.amplitude, a_peak, 1e-10);
  // The sampled maximum is well below it: without the location the test would fail.
  EXPECT_GT(sampled_error, 1e3 * std::abs(peak.amplitude - a_peak));
  EXPECT_GT(sampled_error, 1e-7);
  std::ostringstream text;
  text << fr.points.size() << " points; sampled " << sampled_error << " below, located "
       << peak.amplitude - a_peak << " (omega " << peak.omega - omega_peak << ")";
  RecordProperty("peak", text.str());
  // The same options on a stepped sweep give none; bad DOF indices are refused.
  FrequencyResponseOptions bad = r;
  bad.peaks.dofs = {1};
  EXPECT_THROW(frequency_response(sys, bad), InvalidInput);
}

TEST(Bifurcations, PeriodDoublingOfTheHelmholtzDuffingWellMatchesTheMonodromyMatrix) {
  const HarmonicBalanceSystem sys = well(7);
  FrequencyResponseOptions r = continuation(2.0, 3.6);
  r.stability = true;
  const FrequencyResponse fr = frequency_response(sys, r);
  ASSERT_TRUE(fr.completed) << fr.message;
  std::vector<const Bifurcation*> pd;
  for (const Bifurcation& b : fr.bifurcations) {
    EXPECT_EQ(b.type, BifurcationType::kPeriodDoubling)
        << to_string(b.type) << " at " << b.point.omega;
    if (b.type == BifurcationType::kPeriodDoubling) pd.push_back(&b);
  }
  ASSERT_EQ(pd.size(), 2u);  // into the parametric resonance and out of it
  double worst = 0;
  for (const Bifurcation* b : pd) {
    EXPECT_TRUE(b->located) << b->message;
    // Hill's critical multiplier: real, −1 (its modulus exp(Re μ T), Re μ the test function's
    // zero to the bracket).
    EXPECT_NEAR(b->multiplier.real(), -1.0, 1e-5) << b->point.omega;
    EXPECT_NEAR(b->multiplier.imag(), 0.0, 1e-5) << b->point.omega;
    // The time integration along the located orbit: a real multiplier at −1. The bracket moves
    // it by |dρ/dΩ| · bracket (|dρ/dΩ| ≈ 10 here, the bracket 1.8e-7) and the H = 7 orbit by
    // its truncation (measured below 1e-8 at the Duffing's comparable amplitudes).
    const std::complex<double> rho = nearest_minus_one(
        well_monodromy(sys.unknown_harmonics(), b->point.unknowns, b->point.omega));
    worst = std::max(worst, std::abs(rho + 1.0));
    EXPECT_LE(std::abs(rho + 1.0), 1e-5) << "Ω = " << b->point.omega << ": ρ = " << rho;
    // And on either side of it, at the points that bracket it: one outside the circle, one in.
    const FrequencyPoint &before = fr.points[b->after_point],
                         &after = fr.points[b->after_point + 1];
    const double m0 = std::abs(
        nearest_minus_one(well_monodromy(sys.unknown_harmonics(), before.unknowns, before.omega)));
    const double m1 = std::abs(
        nearest_minus_one(well_monodromy(sys.unknown_harmonics(), after.unknowns, after.omega)));
    EXPECT_LT((m0 - 1) * (m1 - 1), 0) << m0 << " " << m1;
    EXPECT_NE(before.floquet.stable, after.floquet.stable);
  }
  // Between the two period doublings the period-1 orbit is unstable, outside them stable.
  for (size_t i = 0; i < fr.points.size(); ++i) {
    const bool inside =
        static_cast<int>(i) > pd[0]->after_point && static_cast<int>(i) <= pd[1]->after_point;
    EXPECT_EQ(fr.points[i].floquet.stable, !inside) << "Ω = " << fr.points[i].omega;
  }
  std::ostringstream text;
  text << worst << " at " << pd[0]->point.omega << " and " << pd[1]->point.omega << " rad/s";
  RecordProperty("period_doubling_monodromy_distance_from_minus_one", text.str());
}

// Exponents of one solution at Ω = 1 (T = 2π): μ = σ + iν has ρ = e^{σT} e^{iνT}.
FloquetSummary exponents(std::vector<std::complex<double>> mu) {
  FloquetSummary s;
  s.exponents = Eigen::Map<Eigen::VectorXcd>(mu.data(), static_cast<int>(mu.size()));
  return s;
}

TEST(Bifurcations, MultiplierKindsFollowTheAngleOfTheMultiplier) {
  using C = std::complex<double>;
  EXPECT_EQ(multiplier_kind(C(0.1, 0.0), 1.0), MultiplierKind::kPlusOne);
  EXPECT_EQ(multiplier_kind(C(0.1, 3.0), 1.0), MultiplierKind::kPlusOne);  // 3Ω: the same ρ
  EXPECT_EQ(multiplier_kind(C(0.1, 0.5), 1.0), MultiplierKind::kMinusOne);
  EXPECT_EQ(multiplier_kind(C(0.1, -1.5), 1.0), MultiplierKind::kMinusOne);
  EXPECT_EQ(multiplier_kind(C(0.1, 0.3), 1.0), MultiplierKind::kComplex);
  EXPECT_EQ(multiplier_kind(C(0.1, 0.3 * 40), 40.0), MultiplierKind::kComplex);
  // Within kRealMultiplierAngle of the real axis: real.
  const double d = 0.5 * kRealMultiplierAngle / (2 * kPi);
  EXPECT_EQ(multiplier_kind(C(0, d), 1.0), MultiplierKind::kPlusOne);
  EXPECT_EQ(multiplier_kind(C(0, 0.5 - d), 1.0), MultiplierKind::kMinusOne);
  EXPECT_EQ(multiplier_kind(C(0, 3 * d), 1.0), MultiplierKind::kComplex);
  const FloquetSummary s = exponents({C(-0.2, 0.5), C(0.01, 0.3), C(0.02, 0.0)});
  EXPECT_EQ(largest_real_part(s, MultiplierKind::kMinusOne, 1.0), -0.2);
  EXPECT_TRUE(std::isinf(largest_real_part(exponents({C(0.1, 0.3)}), MultiplierKind::kPlusOne, 1)));
  const std::complex<double> rho = critical_multiplier(s, MultiplierKind::kComplex, 1.0);
  EXPECT_NEAR(std::abs(rho), std::exp(0.01 * 2 * kPi), 1e-12);
  EXPECT_NEAR(std::arg(rho), 0.3 * 2 * kPi, 1e-12);
}

// Constructed sequences of exponents along a curve (Ω = 1): which crossing each step shows.
TEST(Bifurcations, CrossingsOfTheUnitCircleAreClassifiedByKind) {
  using C = std::complex<double>;
  using K = MultiplierKind;
  const auto crossings = [](const FloquetSummary& a, const FloquetSummary& b) {
    return unit_circle_crossings(a, 1.0, b, 1.0);
  };
  // Neimark–Sacker: a complex pair leaves the circle (and returns).
  const FloquetSummary ns0 = exponents({C(-0.01, 0.3), C(-0.01, -0.3)});
  const FloquetSummary ns1 = exponents({C(0.01, 0.3), C(0.01, -0.3)});
  EXPECT_EQ(crossings(ns0, ns1), std::vector<K>{K::kComplex});
  EXPECT_EQ(crossings(ns1, ns0), std::vector<K>{K::kComplex});
  // Period doubling: one real multiplier through −1 (Hill gives it as σ ± iΩ/2).
  const FloquetSummary pd0 = exponents({C(-0.01, 0.5), C(-0.2, -0.5)});
  const FloquetSummary pd1 = exponents({C(0.01, 0.5), C(-0.2, -0.5)});
  EXPECT_EQ(crossings(pd0, pd1), std::vector<K>{K::kMinusOne});
  // Fold or branch point: one real multiplier through +1.
  const FloquetSummary f0 = exponents({C(-0.01, 0), C(-0.3, 0)});
  const FloquetSummary f1 = exponents({C(0.01, 0), C(-0.3, 0)});
  EXPECT_EQ(crossings(f0, f1), std::vector<K>{K::kPlusOne});
  // Moving inside or outside the circle without crossing it: nothing.
  EXPECT_TRUE(crossings(ns0, exponents({C(-0.5, 0.2), C(-0.5, -0.2)})).empty());
  EXPECT_TRUE(crossings(ns1, exponents({C(0.3, 0.2), C(0.3, -0.2)})).empty());
  // Within the stability tolerance (1e-7 Ω) of the circle counts as inside.
  EXPECT_TRUE(crossings(f0, exponents({C(0.5e-7, 0), C(-0.3, 0)})).empty());
  // A complex pair outside the circle meeting on the negative real axis changes kind, not side:
  // both kinds are listed, and frequency_response skips them (the kind is missing at one end,
  // and the largest Re μ of all is > 0 at both: no bracket).
  const FloquetSummary out_complex = exponents({C(0.1, 0.45), C(0.1, -0.45)});
  const FloquetSummary out_real = exponents({C(0.15, 0.5), C(0.05, -0.5)});
  EXPECT_EQ(crossings(out_complex, out_real), (std::vector<K>{K::kMinusOne, K::kComplex}));
  EXPECT_TRUE(std::isinf(largest_real_part(out_complex, K::kMinusOne, 1.0)));
  EXPECT_THROW(unit_circle_crossings(f0, 1.0, f1, 1.0, {.stability_tolerance = 0}), InvalidInput);
}

TEST(Bifurcations, SteppedSweepsAndDisabledOptionsGiveNone) {
  const HarmonicBalanceSystem sys = duffing(1);
  FrequencyResponseOptions r = continuation(0.5, 2.0);
  r.bifurcations.enabled = false;
  EXPECT_TRUE(frequency_response(sys, r).bifurcations.empty());
  r.bifurcations = {.tolerance = 0};
  EXPECT_THROW(frequency_response(sys, r), InvalidInput);
  FrequencyResponseOptions s;
  for (double w = 0.5; w <= 2.0; w += 0.05) s.omegas.push_back(w);
  EXPECT_TRUE(frequency_response(sys, s).bifurcations.empty());
}

}  // namespace
}  // namespace stickslip
