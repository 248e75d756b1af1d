// Hill's method (hbm/hill_stability.h) against independent references: the eigenvalues of a
// linear time-invariant system (closed form of its characteristic polynomial), and the monodromy
// matrix of the Duffing oscillator's variational equation integrated in time here (RK4) along the
// harmonic-balance orbit, over the whole frequency response including the unstable middle branch
// between its two folds.
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "continuation/arclength.h"
#include "core/errors.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"
#include "hbm/hill_stability.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;

// Two modes, a linear spring k from DOF 0 to the ground as the "element": the system is linear
// and time-invariant, so its Floquet exponents are its eigenvalues s (mod iΩ): the roots of
// det(s² I + s C + K_stuck) = 0 with K_stuck = diag(ω²) + k ψψᵀ, ψ = Φ row 0.
TEST(HillStability, LinearSystemHasItsDampedEigenvaluesAsExponents) {
  LinearModel model;
  model.omega2 = Eigen::Vector2d(4.0, 25.0);
  model.Phi = (MatrixXd(2, 2) << 0.8, 0.6, -0.6, 0.8).finished();
  model.modal_damping = Eigen::Vector2d(0.05, 0.3);
  const double k = 7.0;
  ContactPair pair{.dofs_a = {0},
                   .dofs_b = {},
                   .frame = MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = k})};
  Excitation e;
  e.harmonics[1] = Eigen::Vector2cd(1.0, 0.0);
  for (const bool coupled : {true, false}) {
    HarmonicBalanceOptions o;
    o.harmonics = 3;
    o.static_coupling = coupled ? StaticCoupling::kCoupled : StaticCoupling::kUncoupled;
    const HarmonicBalanceSystem sys(model, {pair}, e, o);
    const double omega = 1.3;
    const VectorXd x = sys.linear_guess(omega, true);

    // Reference: the 4 x 4 first-order form of s² I + s C + K (modal coordinates).
    const Eigen::Vector2d psi = model.Phi.row(0).transpose();
    const MatrixXd K = MatrixXd(model.omega2.asDiagonal()) + k * psi * psi.transpose();
    const MatrixXd C = model.modal_damping.asDiagonal();
    MatrixXd A = MatrixXd::Zero(4, 4);
    A.topRightCorner(2, 2).setIdentity();
    A.bottomLeftCorner(2, 2) = -K;
    A.bottomRightCorner(2, 2) = -C;
    const Eigen::VectorXcd s = Eigen::EigenSolver<MatrixXd>(A, false).eigenvalues();

    const FloquetSummary f = hill_stability(sys, x, omega, {.dynamic_mode_factor = 0});
    ASSERT_EQ(f.exponents.size(), 4);
    EXPECT_EQ(f.dynamic_modes, 2);
    EXPECT_TRUE(f.stable);
    // Each exponent is an eigenvalue shifted by a whole multiple of iΩ, and each eigenvalue is
    // represented once.
    std::vector<bool> used(4, false);
    for (int i = 0; i < 4; ++i) {
      const std::complex<double> mu = f.exponents[i];
      int match = -1;
      for (int j = 0; j < 4; ++j) {
        const double m = (mu.imag() - s[j].imag()) / omega;
        if (!used[j] && std::abs(mu.real() - s[j].real()) <= 1e-10 &&
            std::abs(m - std::round(m)) <= 1e-10) {
          match = j;
          break;
        }
      }
      ASSERT_GE(match, 0) << (coupled ? "coupled " : "uncoupled ") << mu;
      used[match] = true;
    }
    EXPECT_NEAR(f.max_real_part, std::max(s[0].real(), s[2].real()), 1e-10);
    EXPECT_NEAR(f.max_multiplier, std::exp(f.max_real_part * 2 * kPi / omega), 1e-14);
  }
}

// Duffing: ẍ + c ẋ + ω0² x + k3 x³ = F cos Ωt (the cubic spring as the element).
constexpr double kOmega0 = 1.0, kDamping = 0.02, kCubic = 1.0, kForce = 0.03;

HarmonicBalanceSystem duffing(int harmonics) {
  LinearModel model;
  model.omega2 = VectorXd::Constant(1, kOmega0 * kOmega0);
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
  o.time_samples = 64;  // u³ has harmonics up to 3H = 21 < 32: the AFT is exact
  o.static_coupling = StaticCoupling::kCoupled;
  return HarmonicBalanceSystem(model, {pair}, e, o);
}

// Largest Floquet multiplier modulus of the orbit x(t) = Σ coefficients, from the variational
// equation δẍ + c δẋ + (ω0² + 3 k3 x(t)²) δx = 0 integrated over one period (classical RK4).
double monodromy_max_multiplier(const HarmonicSet& S, const VectorXd& c, double omega) {
  auto displacement = [&](double t) {
    double x = 0;
    for (int p = 0; p < S.size(); ++p) {
      const int k = S.harmonics()[p], o = S.offset(p);
      if (k == 0) {
        x += c[o];
      } else {
        x += c[o] * std::cos(k * omega * t) + c[o + 1] * std::sin(k * omega * t);
      }
    }
    return x;
  };
  auto rate = [&](double t, const Eigen::Matrix2d& P) {
    const double x = displacement(t);
    Eigen::Matrix2d A;
    A << 0, 1, -(kOmega0 * kOmega0 + 3 * kCubic * x * x), -kDamping;
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
  const Eigen::Vector2cd rho = Eigen::EigenSolver<Eigen::Matrix2d>(P, false).eigenvalues();
  return std::max(std::abs(rho[0]), std::abs(rho[1]));
}

TEST(HillStability, DuffingExponentsEqualTheMonodromyMatrixsAlongTheWholeCurve) {
  const HarmonicBalanceSystem sys = duffing(7);
  ArcLengthOptions a;
  a.lambda_start = 0.5;
  a.lambda_end = 2.0;
  a.initial_step = 0.005;
  a.min_step = 1e-7;
  a.max_step = 0.02;
  a.x_scale = 1.0;
  a.newton.tolerance = 1e-12;
  const ContinuationResult r = arclength_continuation(sys, sys.linear_guess(0.5, false), a);
  ASSERT_TRUE(r.completed) << r.message;
  const int n = static_cast<int>(r.points.size());
  ASSERT_GT(n, 50);

  // The middle branch: the points where Ω decreases along the curve (between the folds).
  int unstable_checked = 0, stable_checked = 0, folds = 0;
  double worst = 0;
  for (int i = 1; i + 1 < n; ++i) {
    const double w = r.points[i].lambda;
    const bool before = r.points[i].lambda < r.points[i - 1].lambda;
    const bool after = r.points[i + 1].lambda < r.points[i].lambda;
    if (before != after) {
      ++folds;
      continue;  // a fold point: one multiplier is 1 there
    }
    const FloquetSummary f = hill_stability(sys, r.points[i].x, w);
    EXPECT_EQ(f.stable, !before) << "Ω = " << w;
    (f.stable ? stable_checked : unstable_checked)++;
    // Every fourth point (and all on the middle branch) against the monodromy matrix: the
    // multiplier's logarithm per period, i.e. max Re μ, to 1e-7 of c/2 = 1e-2 (measured 2.5e-9:
    // the orbit is the H = 7 truncation, the RK4 error is ~1e-13).
    if (before || i % 4 == 0) {
      const double reference =
          std::log(monodromy_max_multiplier(sys.unknown_harmonics(), r.points[i].x, w)) * w /
          (2 * kPi);
      worst = std::max(worst, std::abs(f.max_real_part - reference));
      EXPECT_NEAR(f.max_real_part, reference, 1e-7) << "Ω = " << w;
    }
  }
  EXPECT_EQ(folds, 2);
  EXPECT_GT(unstable_checked, 3);
  EXPECT_GT(stable_checked, 20);
  std::ostringstream text;
  text << worst;
  RecordProperty("worst_exponent_difference", text.str());
}

// Jenkins oscillator (m = 1, k = 1e4, c = 2, kt = 5e3, μN = 1, F = 1.5 N): where the element sticks
// over the whole cycle it is the spring kt, and the exponents are those of the stuck linear
// oscillator, −c/2 ± i sqrt(k + kt − c²/4) (mod iΩ); where it slips the periodic solution of this
// dissipative system is stable (the friction only takes energy out).
TEST(HillStability, JenkinsOscillatorIsStableAndStuckPointsHaveTheStuckExponents) {
  const double k = 1e4, c = 2.0, kt = 5e3, fs = 1.0;
  LinearModel model{.omega2 = VectorXd::Constant(1, k),
                    .Phi = MatrixXd::Constant(1, 1, 1.0),
                    .modal_damping = VectorXd::Constant(1, c)};
  ContactPair pair{.dofs_a = {0},
                   .dofs_b = {},
                   .frame = MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<Jenkins1D>(
                       JenkinsParameters{.kt = kt, .mu = 1.0, .normal_load = fs})};
  Excitation e;
  e.harmonics[1] = Eigen::VectorXcd::Constant(1, 1.5);
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 64;
  o.static_coupling = StaticCoupling::kCoupled;
  const HarmonicBalanceSystem sys(model, {pair}, e, o);
  FrequencyResponseOptions r;
  for (double w = 60; w <= 180; w += 4) r.omegas.push_back(w);
  const FrequencyResponse fr = frequency_response(sys, r);
  ASSERT_TRUE(fr.completed) << fr.message;
  const double stuck_re = -c / 2, stuck_im = std::sqrt(k + kt - c * c / 4);
  int stuck = 0, slipping = 0;
  for (const FrequencyPoint& p : fr.points) {
    const FloquetSummary f = hill_stability(sys, p.unknowns, p.omega);
    ASSERT_EQ(f.exponents.size(), 2);
    EXPECT_TRUE(f.stable) << "Ω = " << p.omega << ": max Re μ = " << f.max_real_part;
    if (p.pairs[0].cycle.slip_fraction == 0) {
      ++stuck;
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(f.exponents[i].real(), stuck_re, 1e-9 * stuck_im) << p.omega;
        const double m = (std::abs(f.exponents[i].imag()) - stuck_im) / p.omega;
        EXPECT_NEAR(m, std::round(m), 1e-9 * stuck_im / p.omega) << p.omega;
      }
    } else {
      ++slipping;
      EXPECT_LT(f.max_real_part, 0.0) << p.omega;
    }
  }
  EXPECT_GT(stuck, 5);
  EXPECT_GT(slipping, 5);
}

TEST(HillStability, QuasiStaticHighModesChangeTheExponentsLittle) {
  // A 1-DOF Duffing coupled to a stiff second mode (ω = 40, far above (H+1)Ω): treating it
  // quasi-statically moves the exponents by O((Ω H/ω)²) of its coupling.
  LinearModel model;
  model.omega2 = Eigen::Vector2d(1.0, 1600.0);
  model.Phi = (MatrixXd(2, 2) << 1.0, 0.3, 0.0, 1.0).finished();
  model.modal_damping = Eigen::Vector2d(kDamping, 0.1);
  ContactPair pair{.dofs_a = {0},
                   .dofs_b = {},
                   .frame = MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<CubicSpring>(CubicSpringParameters{.k3 = kCubic})};
  Excitation e;
  e.harmonics[1] = Eigen::Vector2cd(kForce, 0.0);
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.static_coupling = StaticCoupling::kCoupled;
  const HarmonicBalanceSystem sys(model, {pair}, e, o);
  const double w = 1.2;
  NewtonOptions newton;
  newton.tolerance = 1e-12;
  VectorXd x = sys.linear_guess(w, false);
  ASSERT_TRUE(solve_newton(sys, w, x, newton).converged());
  const FloquetSummary all = hill_stability(sys, x, w, {.dynamic_mode_factor = 0});
  const FloquetSummary split = hill_stability(sys, x, w);
  EXPECT_EQ(all.dynamic_modes, 2);
  EXPECT_EQ(split.dynamic_modes, 1);
  EXPECT_EQ(split.quasi_static_modes, 1);
  ASSERT_EQ(split.exponents.size(), 2);
  // The two exponents of the low mode: the full computation has them among its four.
  for (int i = 0; i < 2; ++i) {
    double nearest = 1e300;
    for (int j = 0; j < 4; ++j)
      nearest = std::min(nearest, std::abs(split.exponents[i] - all.exponents[j]));
    EXPECT_LE(nearest, 0.01 * std::abs(split.exponents[i]) + 1e-3) << split.exponents[i];
  }
}

// Modes from 100 rad/s to 1e5 rad/s, one of them double, a linear spring between two DOFs and
// mass-proportional damping c: the system is time-invariant and C = c I in any basis, so every
// exponent is −c/2 ± i √(λ − c²/4), λ the eigenvalues of K_stuck = diag(ω²) + k ψψᵀ (closed form:
// the real part is −c/2 exactly). The companion matrix of the unscaled problem has a norm of
// ω_max² = 1e10, and an eigen-solver that neither scales nor balances it (Eigen's, used before)
// gave real parts off by up to 6e-8 1/s; scaled and balanced (dgeev): 2e-12.
TEST(HillStability, WidelySpreadModesKeepTheirDampingRateToRoundOff) {
  constexpr int n = 6;
  constexpr double c = 5.0, k = 3e6, omega = 300.0;
  LinearModel model;
  model.omega2 = (VectorXd(n) << 1e4, 1e6, 1e6, 1e7, 1e8, 1e10).finished();
  MatrixXd seed(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) seed(i, j) = std::cos(1.0 + 3.7 * i + 1.3 * j * j);
  }
  model.Phi = Eigen::HouseholderQR<MatrixXd>(seed).householderQ() * MatrixXd::Identity(n, n);
  model.modal_damping = VectorXd::Constant(n, c);
  ContactPair pair{.dofs_a = {0},
                   .dofs_b = {1},
                   .frame = MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = k})};
  Excitation e;
  e.harmonics[1] = VectorXd::Unit(n, 0).cast<std::complex<double>>();
  HarmonicBalanceOptions o;
  o.harmonics = 1;
  o.static_coupling = StaticCoupling::kCoupled;
  const HarmonicBalanceSystem sys(model, {pair}, e, o);
  const VectorXd x = sys.linear_guess(omega, true);
  const FloquetSummary f = hill_stability(sys, x, omega, {.dynamic_mode_factor = 0});
  ASSERT_EQ(f.exponents.size(), 2 * n);

  const VectorXd psi = (model.Phi.row(0) - model.Phi.row(1)).transpose();
  const MatrixXd K = MatrixXd(model.omega2.asDiagonal()) + k * psi * psi.transpose();
  const VectorXd lambda = Eigen::SelfAdjointEigenSolver<MatrixXd>(K).eigenvalues();
  for (int i = 0; i < 2 * n; ++i) {
    const std::complex<double> mu = f.exponents[i];
    EXPECT_NEAR(mu.real(), -c / 2, 1e-9) << mu;
    // Im μ = ±√(λ − c²/4) (the centred member: no multiple of Ω added), each λ twice.
    int match = -1;
    for (int j = 0; j < n && match < 0; ++j) {
      if (std::abs(std::abs(mu.imag()) - std::sqrt(lambda[j] - c * c / 4)) <=
          1e-9 * std::sqrt(lambda[j])) {
        match = j;
      }
    }
    ASSERT_GE(match, 0) << mu;
  }
}

// Two modes whose damped frequencies differ by exactly Ω, with equal damping: the families
// μ_1 + imΩ and μ_2 + imΩ of this time-invariant system meet (μ_2 = μ_1 + iΩ, one multiplier), so
// the Hill spectrum has double eigenvalues whose eigenvectors the solver may return mixed (the
// centred member of one family with an outer member of the other), and two centred members with
// one multiplier, which the one-member-per-family rule sees as one family. Reference: the closed
// form, every exponent −c/2 ± iω_d,r with its own ω_d,r (the centred members: Im μ is the mode's
// frequency, no multiple of Ω added), each once. Before the selection resolved such clusters it
// returned one of the two modes twice.
TEST(HillStability, FamiliesThatMeetAreEachPlacedOnce) {
  constexpr double c = 0.2, k = 5.0, omega = 1.3;
  const double wd1 = std::sqrt(4.0 + k - c * c / 4);  // K_stuck = diag(4 + k, ω_2²)
  const double wd2 = wd1 + omega;
  for (const int harmonics : {1, 2, 3}) {
    SCOPED_TRACE(::testing::Message() << "H = " << harmonics);
    LinearModel model;
    model.omega2 = Eigen::Vector2d(4.0, wd2 * wd2 + c * c / 4);
    model.Phi = MatrixXd::Identity(2, 2);
    model.modal_damping = Eigen::Vector2d(c, c);
    ContactPair pair{.dofs_a = {0},
                     .dofs_b = {},
                     .frame = MatrixXd::Constant(1, 1, 1.0),
                     .element = std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = k})};
    Excitation e;
    e.harmonics[1] = Eigen::Vector2cd(1.0, 0.0);
    HarmonicBalanceOptions o;
    o.harmonics = harmonics;
    o.static_coupling = StaticCoupling::kCoupled;
    const HarmonicBalanceSystem sys(model, {pair}, e, o);
    const VectorXd x = sys.linear_guess(omega, true);
    const FloquetSummary f = hill_stability(sys, x, omega, {.dynamic_mode_factor = 0});
    EXPECT_EQ(f.unplaced_exponents, 0);
    ASSERT_EQ(f.exponents.size(), 4);
    std::vector<double> im;
    for (const std::complex<double>& mu : f.exponents) {
      EXPECT_NEAR(mu.real(), -c / 2, 1e-10) << mu;
      im.push_back(mu.imag());
    }
    std::sort(im.begin(), im.end());
    const std::vector<double> expected = {-wd2, -wd1, wd1, wd2};
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(im[i], expected[i], 1e-9 * wd2) << i;
  }
}

TEST(HillStability, BadArgumentsAreRefused) {
  const HarmonicBalanceSystem sys = duffing(1);
  const VectorXd x = VectorXd::Zero(sys.size());
  EXPECT_THROW(hill_stability(sys, x, 0.0), InvalidInput);
  EXPECT_THROW(hill_stability(sys, VectorXd::Zero(sys.size() + 1), 1.0), InvalidInput);
  EXPECT_THROW(hill_stability(sys, x, 1.0, {.dynamic_mode_factor = -1}), InvalidInput);
  EXPECT_THROW(hill_stability(sys, x, 1.0, {.stability_tolerance = 0}), InvalidInput);
}

}  // namespace
}  // namespace stickslip
