// The event AFT (hbm/aft.h, AftMethod::kEvent): force coefficients against closed forms written
// here, the Jacobian against central differences at stick–slip and lift-off cycles, and the
// fall-back to the sampled method where the scalar law does not apply.
#include <array>
#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "core/types.h"
#include "hbm/aft.h"

namespace stickslip {
namespace {

// Closed-form first harmonic of a Jenkins element (kt, slip force Fs) under u = x0 cos θ,
// derived here: the cycle sticks for θ ∈ (0, β) after the reversal at θ = 0 (τ = Fs −
// kt x0 (1 − cos θ)), slips at −Fs on (β, π), and symmetrically, with cos β = 1 − 2Fs/(kt x0).
// a1 = (1/π)∮ τ cos θ = kt x0 (β − sin 2β / 2)/π, b1 = −(4Fs/π)(1 − Fs/(kt x0)).
std::array<double, 2> jenkins_first_harmonic(double kt, double fs, double x0) {
  if (kt * x0 <= fs) return {kt * x0, 0.0};
  const double beta = std::acos(1 - 2 * fs / (kt * x0));
  return {kt * x0 * (beta - 0.5 * std::sin(2 * beta)) / kPi, -4 * fs / kPi * (1 - fs / (kt * x0))};
}

TEST(EventAft, JenkinsFirstHarmonicEqualsDescribingFunctionWithSixteenSamples) {
  // Exact up to round-off: transitions located by Newton, Gauss–Legendre per segment.
  constexpr double kTolerance = 1e-10;
  const double kt = 1e5, fs = 20.0;  // x_cr = 2e-4
  const Jenkins1D element({.kt = kt, .mu = 0.4, .normal_load = 50});
  const Aft aft(FourierBasis(HarmonicSet::up_to(1), 16), AftMethod::kEvent);
  for (double x0 : {1e-4, 2e-4, 2.0001e-4, 2.05e-4, 3e-4, 1e-3, 1e-2}) {
    for (double phase : {0.0, 0.3, 0.9, 2.5}) {
      Eigen::VectorXd c(3), F;
      c << 1e-5, x0 * std::cos(phase), x0 * std::sin(phase);  // u = u0 + x0 cos(θ − phase)
      const CycleStatistics st = aft.evaluate(element, c, Eigen::VectorXd(), F, nullptr);
      EXPECT_FALSE(st.aft_fallback);
      const auto [a1, b1] = jenkins_first_harmonic(kt, fs, x0);
      const std::complex<double> expected =
          std::complex<double>(a1, -b1) * std::exp(std::complex<double>(0, -phase));
      const std::complex<double> got(F[1], -F[2]);
      EXPECT_LE(std::abs(got - expected), kTolerance * std::abs(expected))
          << "x0 = " << x0 << " phase = " << phase << " got " << got << " expected " << expected;
      // Mean force: 0 in a slipping cycle (symmetric), kt u0 in the stuck one from the virgin
      // state.
      // (With the mean u0 the virgin path slips once if kt (u0 + x0) > Fs; the stuck cycle then
      // spans [Fs − 2 kt x0, Fs]: mean Fs − kt x0.)
      const double mean =
          kt * x0 > fs ? 0.0 : (kt * (1e-5 + x0) <= fs ? kt * 1e-5 : fs - kt * x0);
      EXPECT_NEAR(F[0], mean, kTolerance * fs) << "x0 = " << x0;
      // Energy per cycle 4 Fs (x0 − Fs/kt) when slipping (= −π x0 b1).
      const double energy = kt * x0 <= fs ? 0.0 : 4 * fs * (x0 - fs / kt);
      EXPECT_NEAR(st.dissipated_energy, energy, 1e-10 * fs * x0) << "x0 = " << x0;
    }
  }
}

struct Case {
  std::string label;
  ElementPtr element;
  Eigen::VectorXd c;  // m·nc, H = 3 with harmonic 0 (nc = 7)
  bool lifts_off = false;
  double alpha = 0.0;  // 3D: tangential direction e = (cos α, sin α)
};

// Random smooth signals: mean, harmonic 1 (a1, b1), smaller 2nd and 3rd.
Eigen::VectorXd signal(double mean, double a1, double b1, std::mt19937& rng) {
  std::uniform_real_distribution<double> small(-0.15, 0.15);
  const double amp = std::hypot(a1, b1);
  Eigen::VectorXd c(7);
  c << mean, a1, b1, amp * small(rng), amp * small(rng), amp * small(rng), amp * small(rng);
  return c;
}

// 3D contact coefficients with the tangential motion along e = (cos α, sin α).
Eigen::VectorXd contact(const Eigen::VectorXd& s, const Eigen::VectorXd& w, double alpha) {
  Eigen::VectorXd c(21);
  c << std::cos(alpha) * s, std::sin(alpha) * s, w;
  return c;
}

std::vector<Case> cases() {
  std::mt19937 rng(3);
  std::vector<Case> out;
  auto jenkins =
      std::make_shared<Jenkins1D>(JenkinsParameters{.kt = 1e5, .mu = 0.4, .normal_load = 50});
  out.push_back({"jenkins_slip", jenkins, signal(1e-5, 8e-4, 3e-4, rng)});
  out.push_back({"jenkins_barely_slips", jenkins, signal(1e-5, 2.3e-4, 0.5e-4, rng)});
  auto c3 = std::make_shared<FrictionContact3D>(
      FrictionContactParameters{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0});
  out.push_back({"3d_slip_t1", c3,
                 contact(signal(0, 3e-4, 1e-4, rng), signal(0, 1e-5, 2e-6, rng), 0.0)});
  out.push_back({"3d_slip_oblique", c3,
                 contact(signal(1e-6, 2e-4, -1e-4, rng), signal(0, 2e-5, 1e-5, rng), 0.7), false,
                 0.7});
  out.push_back({"3d_liftoff", c3,
                 contact(signal(0, 4e-5, 2e-5, rng), signal(0, 9e-5, 3e-5, rng), 0.0), true});
  out.push_back({"3d_liftoff_oblique", c3,
                 contact(signal(0, 1e-4, -3e-5, rng), signal(-1e-5, 6e-5, 5e-5, rng), -1.2),
                 true, -1.2});
  auto gap = std::make_shared<FrictionContact3D>(
      FrictionContactParameters{.kt = 1e6, .kn = 2e6, .mu = 0.3, .gap = 1e-5});
  out.push_back({"3d_gap", gap,
                 contact(signal(0, 1e-5, 5e-6, rng), signal(2e-5, 2e-5, 2e-5, rng), 0.4), true, 0.4});
  return out;
}

TEST(EventAft, JacobianMatchesCentralDifferencesAtStickSlipAndLiftOff) {
  // h = 1e-7 of the coefficient scale: O(h²) truncation and O(eps/h) round-off ≲ 1e-8 relative.
  // The perturbations perpendicular to the tangential line leave the collinear case: kEvent falls
  // back to sampled on both sides (the ⊥ block is the sampled method's, consistently), kEventPlanar
  // takes the planar method on both sides (the Jacobian is the planar method's there).
  constexpr double kFdRelativeTolerance = 1e-6;
  for (const AftMethod method : {AftMethod::kEvent, AftMethod::kEventPlanar})
  for (const Case& c : cases()) {
    const Aft aft(FourierBasis(HarmonicSet::up_to(3), 64), method);
    SCOPED_TRACE(c.label + (method == AftMethod::kEvent ? " (event)" : " (event_planar)"));
    Eigen::VectorXd F;
    Eigen::MatrixXd J;
    const CycleStatistics st = aft.evaluate(*c.element, c.c, Eigen::VectorXd(), F, &J);
    EXPECT_FALSE(st.aft_fallback);
    EXPECT_GT(st.slip_fraction, 0.0);
    EXPECT_GT(st.stick_fraction, 0.0);
    if (c.lifts_off) {
      EXPECT_GT(st.separation_fraction, 0.0);
    }
    // Directions: the unit vectors, with the tangential pairs (t1, t2) turned to (e, e⊥).
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(J.cols(), J.cols());
    if (J.cols() == 21) {
      const double ca = std::cos(c.alpha), sa = std::sin(c.alpha);
      for (int i = 0; i < 7; ++i) {
        T(i, i) = ca;
        T(7 + i, i) = sa;
        T(i, 7 + i) = -sa;
        T(7 + i, 7 + i) = ca;
      }
    }
    J = J * T;
    const double h = 1e-7 * c.c.cwiseAbs().maxCoeff();
    Eigen::MatrixXd fd(J.rows(), J.cols());
    for (Eigen::Index q = 0; q < c.c.size(); ++q) {
      Eigen::VectorXd cp = c.c + h * T.col(q), cm = c.c - h * T.col(q), Fp, Fm;
      aft.evaluate(*c.element, cp, Eigen::VectorXd(), Fp, nullptr);
      aft.evaluate(*c.element, cm, Eigen::VectorXd(), Fm, nullptr);
      fd.col(q) = (Fp - Fm) / (2 * h);
    }
    std::string blocks;
    for (Eigen::Index a = 0; a < J.rows() / 7; ++a) {
      for (Eigen::Index b = 0; b < J.cols() / 7; ++b) {
        blocks += " [" + std::to_string(a) + std::to_string(b) + "] " +
                  std::to_string((fd - J).block(7 * a, 7 * b, 7, 7).norm()) + "/" +
                  std::to_string(J.block(7 * a, 7 * b, 7, 7).norm());
      }
    }
    EXPECT_LE((fd - J).norm(), kFdRelativeTolerance * J.norm()) << blocks;
  }
}

TEST(EventAft, SampledMethodConvergesToTheEventForces) {
  // The sampled law is the event law's limit N → ∞ (rate-independent law): its error falls with
  // N; at N = 65536 it is below 1e-5 of the force scale for these cycles.
  const Aft event(FourierBasis(HarmonicSet::up_to(3), 64), AftMethod::kEvent);
  const Aft coarse(FourierBasis(HarmonicSet::up_to(3), 1024));
  const Aft fine(FourierBasis(HarmonicSet::up_to(3), 65536));
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    Eigen::VectorXd Fe, Fc, Ff;
    event.evaluate(*c.element, c.c, Eigen::VectorXd(), Fe, nullptr);
    coarse.evaluate(*c.element, c.c, Eigen::VectorXd(), Fc, nullptr);
    fine.evaluate(*c.element, c.c, Eigen::VectorXd(), Ff, nullptr);
    EXPECT_LT((Ff - Fe).norm(), 1e-5 * Fe.norm());
    EXPECT_LT((Ff - Fe).norm(), (Fc - Fe).norm());
  }
}

TEST(EventAft, OtherElementsAndNonCollinearMotionFallBackToSampled) {
  const Aft event(FourierBasis(HarmonicSet::up_to(3), 64), AftMethod::kEvent);
  const Aft sampled(FourierBasis(HarmonicSet::up_to(3), 64));
  std::mt19937 rng(5);
  const auto c3 = std::make_shared<FrictionContact3D>(
      FrictionContactParameters{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0});
  Eigen::VectorXd c(21);
  c << signal(0, 3e-4, 1e-4, rng), signal(0, -1e-4, 2e-4, rng), signal(0, 1e-5, 0, rng);
  const UnilateralSpring spring({.k = 1e4, .gap = 1e-3});
  const Eigen::VectorXd cu = signal(1e-3, 2e-3, 1e-3, rng);
  Eigen::VectorXd Fe, Fs;
  EXPECT_TRUE(event.evaluate(*c3, c, Eigen::VectorXd(), Fe, nullptr).aft_fallback);
  sampled.evaluate(*c3, c, Eigen::VectorXd(), Fs, nullptr);
  EXPECT_EQ(Fe, Fs);
  EXPECT_TRUE(event.evaluate(spring, cu, Eigen::VectorXd(), Fe, nullptr).aft_fallback);
  sampled.evaluate(spring, cu, Eigen::VectorXd(), Fs, nullptr);
  EXPECT_EQ(Fe, Fs);
}

TEST(EventAft, OffsetActsAsAFrozenMean) {
  const Aft aft(FourierBasis(HarmonicSet::up_to(3), 64), AftMethod::kEvent);
  const Case c = cases()[4];
  Eigen::VectorXd offset(3), F1, F2;
  offset << 1e-6, 0.0, 3e-6;
  Eigen::VectorXd shifted = c.c;
  for (int d = 0; d < 3; ++d) shifted[7 * d] += offset[d];
  aft.evaluate(*c.element, c.c, offset, F1, nullptr);
  aft.evaluate(*c.element, shifted, Eigen::VectorXd(), F2, nullptr);
  EXPECT_LT((F1 - F2).norm(), 1e-12 * F2.norm());
}

}  // namespace
}  // namespace stickslip
