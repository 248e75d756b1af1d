// AFT: the exact harmonic Jacobian ∂F/∂c against central differences and the Taylor-remainder
// slope, for every element type in stick, slip, lift-off and mixed cycles; and the AFT force
// coefficients of a Jenkins element against the closed-form describing function.
#include "hbm/aft.h"

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../derivative_check.h"
#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "core/types.h"

namespace stickslip {
namespace {

struct Case {
  std::string label;
  ElementPtr element;
  Eigen::VectorXd c;  // m·nc coefficients, H = 3 with harmonic 0 (nc = 7)
};

// Coefficients for component amplitudes: mean, first-harmonic (a1, b1) and a smaller 2nd/3rd.
Eigen::VectorXd coefficients(const std::vector<std::array<double, 3>>& comps, std::mt19937& rng) {
  std::uniform_real_distribution<double> small(-0.15, 0.15);
  Eigen::VectorXd c(7 * comps.size());
  for (size_t d = 0; d < comps.size(); ++d) {
    const auto [mean, a1, b1] = comps[d];
    const double amp = std::hypot(a1, b1);
    c.segment(7 * d, 7) << mean, a1, b1, amp * small(rng), amp * small(rng), amp * small(rng),
        amp * small(rng);
  }
  return c;
}

std::vector<Case> cases() {
  std::mt19937 rng(7);
  std::vector<Case> out;
  auto contact = std::make_shared<FrictionContact3D>(
      FrictionContactParameters{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0});
  out.push_back({"3d_stick", contact,
                 coefficients({{1e-6, 1e-5, 4e-6}, {0, -5e-6, 8e-6}, {0, 1e-6, 2e-6}}, rng)});
  out.push_back(
      {"3d_slip", contact, coefficients({{0, 3e-4, 1e-4}, {0, -1e-4, 2e-4}, {0, 1e-5, 0}}, rng)});
  out.push_back({"3d_liftoff", contact,
                 coefficients({{0, 2e-5, 1e-5}, {0, 1e-5, -1e-5}, {0, 9e-5, 3e-5}}, rng)});
  out.push_back({"3d_mixed", contact,
                 coefficients({{0, 6e-5, 2e-5}, {0, 1e-5, -4e-5}, {2e-5, 5e-5, 3e-5}}, rng)});
  auto gap_contact = std::make_shared<FrictionContact3D>(
      FrictionContactParameters{.kt = 1e6, .kn = 2e6, .mu = 0.3, .gap = 1e-5});
  out.push_back({"3d_gap", gap_contact,
                 coefficients({{0, 1e-5, 5e-6}, {0, 2e-6, -4e-6}, {2e-5, 2e-5, 2e-5}}, rng)});
  auto jenkins =
      std::make_shared<Jenkins1D>(JenkinsParameters{.kt = 1e5, .mu = 0.4, .normal_load = 50});
  out.push_back({"jenkins_stick", jenkins, coefficients({{1e-5, 4e-5, 2e-5}}, rng)});
  out.push_back({"jenkins_slip", jenkins, coefficients({{1e-5, 8e-4, 3e-4}}, rng)});
  auto gap = std::make_shared<UnilateralSpring>(UnilateralSpringParameters{.k = 1e4, .gap = 1e-3});
  out.push_back({"unilateral", gap, coefficients({{1e-3, 2e-3, 1e-3}}, rng)});
  auto cubic = std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = 1e3, .k3 = 1e9});
  out.push_back({"cubic", cubic, coefficients({{1e-4, 1e-3, 5e-4}}, rng)});
  return out;
}

const Aft& aft() {
  static const Aft a(FourierBasis(HarmonicSet::up_to(3), 64));
  return a;
}

TEST(Aft, JacobianMatchesCentralDifferencesForEveryElementAndRegime) {
  // h = 1e-7 of the coefficient scale: O(h²) truncation and O(eps/h) round-off both ≲ 1e-8
  // relative; no sample changes regime within ±h for these generic cycles.
  constexpr double kFdRelativeTolerance = 1e-6;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    Eigen::VectorXd F;
    Eigen::MatrixXd J;
    aft().evaluate(*c.element, c.c, Eigen::VectorXd(), F, &J);
    const double h = 1e-7 * c.c.cwiseAbs().maxCoeff();
    Eigen::MatrixXd fd(J.rows(), J.cols());
    for (Eigen::Index q = 0; q < c.c.size(); ++q) {
      Eigen::VectorXd cp = c.c, cm = c.c, Fp, Fm;
      cp[q] += h;
      cm[q] -= h;
      aft().evaluate(*c.element, cp, Eigen::VectorXd(), Fp, nullptr);
      aft().evaluate(*c.element, cm, Eigen::VectorXd(), Fm, nullptr);
      fd.col(q) = (Fp - Fm) / (2 * h);
    }
    EXPECT_LE((fd - J).norm(), kFdRelativeTolerance * J.norm());
  }
}

TEST(Aft, JacobianTaylorRemainderFallsQuadratically) {
  // tests/derivative_check.h. Where the cycle is piecewise linear in c (stick, open contact,
  // closed unilateral spring) the remainder is round-off; otherwise it falls like h² until a
  // sample crosses a regime boundary at larger h.
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    Eigen::VectorXd F, d(c.c.size());
    Eigen::MatrixXd J;
    aft().evaluate(*c.element, c.c, Eigen::VectorXd(), F, &J);
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = normal(rng);
    d *= c.c.norm() / d.norm();
    const auto F_at = [&](double h) {
      Eigen::VectorXd Fh;
      aft().evaluate(*c.element, c.c + h * d, Eigen::VectorXd(), Fh, nullptr);
      return Fh;
    };
    testing::expect_taylor_slope(testing::taylor_remainder(F_at, F, J * d));
  }
}

TEST(Aft, OffsetActsAsAFrozenMean) {
  // u0 added to every sample ≡ the same value in the harmonic-0 coefficient.
  const Case c = cases()[3];
  Eigen::VectorXd offset(3), F1, F2;
  offset << 1e-6, -2e-6, 3e-6;
  Eigen::VectorXd shifted = c.c;
  for (int d = 0; d < 3; ++d) shifted[7 * d] += offset[d];
  aft().evaluate(*c.element, c.c, offset, F1, nullptr);
  aft().evaluate(*c.element, shifted, Eigen::VectorXd(), F2, nullptr);
  EXPECT_LT((F1 - F2).norm(), 1e-12 * F2.norm());
}

// Closed-form first harmonic of a Jenkins element (kt, slip force Fs) under u = x0 cos θ
// (thesis eqs. 2.24–2.25, rederived): a1 = kt x0 (β − sin2β/2)/π with cos β = 1 − 2Fs/(kt x0),
// b1 = −(4Fs/π)(1 − Fs/(kt x0)) for x0 > Fs/kt; a1 = kt x0, b1 = 0 in stick.
std::array<double, 2> jenkins_first_harmonic(double kt, double fs, double x0) {
  if (kt * x0 <= fs) return {kt * x0, 0.0};
  const double beta = std::acos(1 - 2 * fs / (kt * x0));
  return {kt * x0 * (beta - 0.5 * std::sin(2 * beta)) / kPi, -4 * fs / kPi * (1 - fs / (kt * x0))};
}

TEST(Aft, JenkinsFirstHarmonicMatchesDescribingFunction) {
  // The sampled cycle is exact at the samples (rate-independent law, piecewise-linear input);
  // the only error is the rectangle rule on a force with a slope jump at the stick→slip
  // transitions: O((2π/N)²) relative, ≈ 2e-6 at N = 4096 (measured below 1e-6).
  constexpr double kDescribingFunctionTolerance = 2e-6;
  const double kt = 1e5, fs = 20.0;  // x_cr = 2e-4
  const Jenkins1D element({.kt = kt, .mu = 0.4, .normal_load = 50});
  const Aft fine(FourierBasis(HarmonicSet::up_to(1), 4096));
  for (double x0 : {1e-4, 2e-4, 2.05e-4, 3e-4, 1e-3, 1e-2}) {
    for (double phase : {0.0, 0.9}) {
      Eigen::VectorXd c(3), F;
      c << 0, x0 * std::cos(phase), x0 * std::sin(phase);  // u = x0 cos(θ − phase)
      fine.evaluate(element, c, Eigen::VectorXd(), F, nullptr);
      const auto [a1, b1] = jenkins_first_harmonic(kt, fs, x0);
      // Rotate the closed form (given for phase 0) by the phase: X_F = (a1 − i b1) e^{−i phase}.
      const std::complex<double> expected =
          std::complex<double>(a1, -b1) * std::exp(std::complex<double>(0, -phase));
      const std::complex<double> got(F[1], -F[2]);
      EXPECT_LE(std::abs(got - expected), kDescribingFunctionTolerance * std::abs(expected))
          << "x0 = " << x0 << " phase = " << phase;
      EXPECT_NEAR(F[0], 0.0, 1e-9 * fs);
    }
  }
}

}  // namespace
}  // namespace stickslip
