// One-harmonic balance of the Duffing oscillator, written here as a 2-unknown R(x, Ω):
//   ẍ + c ẋ + ω0² x + k3 x³ = F cos Ωt,  x(t) ≈ a cos Ωt + b sin Ωt,  A² = a² + b²,
//   R = [(ω0² − Ω²) a + cΩ b + ¾k3 A² a − F;  (ω0² − Ω²) b − cΩ a + ¾k3 A² b].
// Its frequency–amplitude relation in closed form:
//   G(A, Ω) = ((ω0² − Ω² + ¾k3 A²)² + (cΩ)²) A² − F² = 0,
// a cubic in A² at fixed Ω (three real roots inside the hysteresis band), and a quadratic in Ω² at
// fixed A. With hardening (k3 > 0) and enough forcing the curve folds twice: a jump-down
// frequency Ω_down (sweeping up) and a jump-up frequency Ω_up < Ω_down (sweeping down), both
// local extrema of the larger Ω root of the quadratic.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "continuation/arclength.h"
#include "continuation/sweep.h"
#include "test_systems.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kOmega0 = 1.0, kDamping = 0.02, kCubic = 1.0, kForce = 0.03;
constexpr double kOmegaMin = 0.5, kOmegaMax = 2.0;

testing::FunctionSystem duffing() {
  return testing::FunctionSystem(
      2,
      [](const VectorXd& x, double w, VectorXd& R, MatrixXd* J, VectorXd* Rl) {
        const double a = x(0), b = x(1), A2 = a * a + b * b, k = 0.75 * kCubic;
        const double d = kOmega0 * kOmega0 - w * w;
        R << d * a + kDamping * w * b + k * A2 * a - kForce, d * b - kDamping * w * a + k * A2 * b;
        if (J) {
          *J << d + k * (3 * a * a + b * b), kDamping * w + 2 * k * a * b,
              -kDamping * w + 2 * k * a * b, d + k * (a * a + 3 * b * b);
        }
        if (Rl) *Rl << -2 * w * a + kDamping * b, -2 * w * b - kDamping * a;
      },
      kForce);
}

double amplitude(const VectorXd& x) { return std::hypot(x(0), x(1)); }

// G(A, Ω) / F²: HB residual ||R|| <= 1e-8 F gives |G| / F² <= 2e-8 to first order.
double closed_form_residual(double A, double w) {
  const double p = kOmega0 * kOmega0 - w * w + 0.75 * kCubic * A * A;
  return ((p * p + kDamping * kDamping * w * w) * A * A - kForce * kForce) / (kForce * kForce);
}
constexpr double kClosedFormTolerance = 1e-7;

// Real roots A of G(A, Ω) = 0 at fixed Ω, ascending: the cubic in q = A² by its companion matrix.
std::vector<double> amplitudes_at(double w) {
  const double k = 0.75 * kCubic, d = kOmega0 * kOmega0 - w * w;
  // q³ + c2 q² + c1 q + c0 = 0 after dividing by k².
  const double c2 = 2 * d / k, c1 = (d * d + kDamping * kDamping * w * w) / (k * k),
               c0 = -kForce * kForce / (k * k);
  Eigen::Matrix3d companion;
  companion << 0, 0, -c0, 1, 0, -c1, 0, 1, -c2;
  const Eigen::Vector3cd q = companion.eigenvalues();
  std::vector<double> A;
  for (const auto& r : q) {
    if (std::abs(r.imag()) <= 1e-9 * std::abs(r) && r.real() > 0) A.push_back(std::sqrt(r.real()));
  }
  std::sort(A.begin(), A.end());
  return A;
}

// The larger root Ω₊(A) of G(A, Ω) = 0 seen as a quadratic in Ω² (NaN above the peak amplitude).
double omega_plus(double A) {
  const double p = kOmega0 * kOmega0 + 0.75 * kCubic * A * A, c2 = kDamping * kDamping;
  const double disc = (2 * p - c2) * (2 * p - c2) - 4 * (p * p - kForce * kForce / (A * A));
  return disc < 0 ? std::nan("") : std::sqrt(0.5 * ((2 * p - c2) + std::sqrt(disc)));
}

// The fold frequencies (Ω_up, Ω_down): the local minimum and maximum of Ω₊(A), by dense sampling
// refined by golden-section search.
struct Folds {
  double omega_up, omega_down;
};
Folds fold_frequencies() {
  auto refine = [](double lo, double hi, double sign) {  // maximises sign · Ω₊ on [lo, hi]
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int i = 0; i < 100; ++i) {
      const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
      if (sign * omega_plus(m1) > sign * omega_plus(m2)) {
        hi = m2;
      } else {
        lo = m1;
      }
    }
    return omega_plus(0.5 * (lo + hi));
  };
  constexpr int kSamples = 20000;
  constexpr double kAmax = 3.0;  // above the peak amplitude (about 1.09)
  Folds f{std::nan(""), std::nan("")};
  double prev2 = std::nan(""), prev1 = std::nan("");
  for (int i = 1; i <= kSamples; ++i) {
    const double A = kAmax * i / kSamples, h = kAmax / kSamples;
    const double w = omega_plus(A);
    if (!std::isnan(prev2) && !std::isnan(w)) {
      if (prev1 < prev2 && prev1 < w) f.omega_up = refine(A - 2 * h, A, -1);
      if (prev1 > prev2 && prev1 > w) f.omega_down = refine(A - 2 * h, A, 1);
    }
    prev2 = prev1;
    prev1 = w;
  }
  return f;
}

TEST(Duffing, HarmonicBalanceJacobianMatchesFiniteDifferences) {
  testing::expect_jacobians_match_finite_differences(duffing(), VectorXd{{0.4, -0.7}}, 1.2);
}

TEST(Duffing, ReferenceFoldsExist) {
  const Folds f = fold_frequencies();
  ASSERT_TRUE(std::isfinite(f.omega_up) && std::isfinite(f.omega_down));
  EXPECT_LT(kOmegaMin, f.omega_up);
  EXPECT_LT(f.omega_up, f.omega_down);
  EXPECT_LT(f.omega_down, kOmegaMax);
  // Inside the band the cubic has three real roots, outside one.
  EXPECT_EQ(amplitudes_at(0.5 * (f.omega_up + f.omega_down)).size(), 3u);
  EXPECT_EQ(amplitudes_at(0.5 * (kOmegaMin + f.omega_up)).size(), 1u);
  EXPECT_EQ(amplitudes_at(0.5 * (kOmegaMax + f.omega_down)).size(), 1u);
}

TEST(Duffing, ArcLengthFollowsTheFrequencyResponseThroughBothFolds) {
  const testing::FunctionSystem sys = duffing();
  const Folds folds = fold_frequencies();
  // x_scale = 1 (about the peak amplitude) and automatic scaling (||x|| at Ω_min, 27 times
  // smaller: many more points through the peak, same curve).
  for (double x_scale : {1.0, 0.0}) {
    SCOPED_TRACE(x_scale);
    ArcLengthOptions o;
    o.lambda_start = kOmegaMin;
    o.lambda_end = kOmegaMax;
    o.x_scale = x_scale;
    o.initial_step = 1e-3;
    o.min_step = 1e-7;
    o.max_step = x_scale > 0 ? 0.01 : 0.2;  // similar resolution in x for both scalings
    const ContinuationResult r = arclength_continuation(sys, VectorXd::Zero(2), o);
    ASSERT_TRUE(r.completed) << r.message;

    std::vector<double> omega, A;
    double max_jump = 0;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      const ContinuationPoint& p = r.points[i];
      ASSERT_TRUE(p.newton.converged());
      omega.push_back(p.lambda);
      A.push_back(amplitude(p.x));
      EXPECT_LE(std::abs(closed_form_residual(A.back(), omega.back())), kClosedFormTolerance)
          << "Omega " << omega.back() << " A " << A.back();
      if (i > 0) max_jump = std::max(max_jump, (r.points[i].x - r.points[i - 1].x).norm());
    }
    EXPECT_EQ(omega.front(), kOmegaMin);
    EXPECT_EQ(omega.back(), kOmegaMax);
    // The ends are on the single-valued parts: the only root of the cubic.
    constexpr double kAmplitudeTolerance = 1e-7;  // ||R|| <= 1e-8 F, well-conditioned there
    EXPECT_NEAR(A.front(), amplitudes_at(kOmegaMin).front(), kAmplitudeTolerance);
    EXPECT_NEAR(A.back(), amplitudes_at(kOmegaMax).front(), kAmplitudeTolerance);

    // Exactly two turning points, at the closed-form fold frequencies (to the resolution of the
    // steps: Ω departs from a fold quadratically in the distance along the curve).
    constexpr double kFoldResolution = 1e-3;
    int reversals = 0;
    for (std::size_t i = 1; i + 1 < omega.size(); ++i) {
      const bool max = omega[i] > omega[i - 1] && omega[i] >= omega[i + 1];
      const bool min = omega[i] < omega[i - 1] && omega[i] <= omega[i + 1];
      if (max) {
        ++reversals;
        EXPECT_LE(omega[i], folds.omega_down + 1e-9);
        EXPECT_GE(omega[i], folds.omega_down - kFoldResolution);
      }
      if (min) {
        ++reversals;
        EXPECT_GE(omega[i], folds.omega_up - 1e-9);
        EXPECT_LE(omega[i], folds.omega_up + kFoldResolution);
      }
    }
    EXPECT_EQ(reversals, 2);
    // No branch lost: the path is continuous (no step longer than max_step allows, with the x
    // part weighted by x_scale / lambda_scale; factor 2 for chord vs pseudo arc length) and
    // passes through every amplitude up to the peak: the three roots at mid-band are all visited.
    const double x_scale_used = x_scale > 0 ? x_scale : r.points.front().x.norm();
    EXPECT_LE(max_jump, 2 * o.max_step * x_scale_used / (kOmegaMax - kOmegaMin));
    const double w_mid = 0.5 * (folds.omega_up + folds.omega_down);
    for (double A_root : amplitudes_at(w_mid)) {
      double closest = 1e9;
      for (std::size_t i = 0; i + 1 < omega.size(); ++i) {
        if ((omega[i] - w_mid) * (omega[i + 1] - w_mid) <= 0) {  // the path crosses Ω_mid here
          const double s = (w_mid - omega[i]) / (omega[i + 1] - omega[i]);
          closest = std::min(closest, std::abs(A[i] + s * (A[i + 1] - A[i]) - A_root));
        }
      }
      // Linear interpolation between points |ΔA| <= 0.0133 apart on a smooth curve.
      EXPECT_LT(closest, 1e-3) << "root A = " << A_root << " not visited";
    }
    RecordProperty(x_scale > 0 ? "points_x_scale_1" : "points_auto", int(r.points.size()));
  }
}

TEST(Duffing, SteppedSweepUpAndDownShowsTheHysteresis) {
  const testing::FunctionSystem sys = duffing();
  const Folds folds = fold_frequencies();
  constexpr double kStep = 0.005;
  std::vector<double> up;
  for (int i = 0; kOmegaMin + i * kStep <= kOmegaMax + 1e-12; ++i)
    up.push_back(kOmegaMin + i * kStep);
  const std::vector<double> down(up.rbegin(), up.rend());

  const ContinuationResult r_up = stepped_sweep(sys, VectorXd::Zero(2), up, {});
  const ContinuationResult r_down = stepped_sweep(sys, VectorXd::Zero(2), down, {});
  ASSERT_TRUE(r_up.completed) << r_up.message;
  ASSERT_TRUE(r_down.completed) << r_down.message;
  std::vector<double> A_up, A_down(up.size());
  for (std::size_t i = 0; i < up.size(); ++i) {
    A_up.push_back(amplitude(r_up.points[i].x));
    A_down[up.size() - 1 - i] = amplitude(r_down.points[i].x);
    EXPECT_LE(std::abs(closed_form_residual(A_up.back(), up[i])), kClosedFormTolerance);
    EXPECT_LE(std::abs(closed_form_residual(A_down[up.size() - 1 - i], down[i])),
              kClosedFormTolerance);
  }
  // Inside the band the sweep up rides the upper branch (largest root), the sweep down the lower
  // (smallest root).
  constexpr double kAmplitudeTolerance = 1e-6;  // well-separated roots, ||R|| <= 1e-8 F
  int inside = 0;
  for (std::size_t i = 0; i < up.size(); ++i) {
    const double margin = 2 * kStep;  // stay off the folds, where roots merge
    if (up[i] > folds.omega_up + margin && up[i] < folds.omega_down - margin) {
      const std::vector<double> roots = amplitudes_at(up[i]);
      ASSERT_EQ(roots.size(), 3u);
      EXPECT_NEAR(A_up[i], roots.back(), kAmplitudeTolerance) << "Omega " << up[i];
      EXPECT_NEAR(A_down[i], roots.front(), kAmplitudeTolerance) << "Omega " << up[i];
      EXPECT_GT(A_up[i], 2 * A_down[i]);
      ++inside;
    } else if (up[i] < folds.omega_up - margin || up[i] > folds.omega_down + margin) {
      EXPECT_NEAR(A_up[i], A_down[i], kAmplitudeTolerance) << "Omega " << up[i];
    }
  }
  EXPECT_GT(inside, 10);
  // The jumps happen where the branch ends: the largest drop of the sweep up between the two
  // grid frequencies around Ω_down, the largest rise of the sweep down around Ω_up.
  std::size_t i_drop = 0, i_rise = 0;
  for (std::size_t i = 0; i + 1 < up.size(); ++i) {
    if (A_up[i] - A_up[i + 1] > A_up[i_drop] - A_up[i_drop + 1]) i_drop = i;
    if (A_down[i] - A_down[i + 1] > A_down[i_rise] - A_down[i_rise + 1]) i_rise = i;
  }
  EXPECT_LE(up[i_drop], folds.omega_down);
  EXPECT_GT(up[i_drop + 1], folds.omega_down);
  EXPECT_LT(up[i_rise], folds.omega_up);
  EXPECT_GE(up[i_rise + 1], folds.omega_up);
}

}  // namespace
}  // namespace stickslip
