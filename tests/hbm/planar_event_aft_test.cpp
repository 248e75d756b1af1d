// The event AFT with general tangential motion in the contact plane (issue 25; hbm/aft.h,
// event_aft_planar.cpp): a circular orbit against its closed form derived here, elliptical
// cycles (and one stuck after slipping in its transient) against the sampled law's limit, and the
// Jacobian against central differences at elliptical stick–slip, stuck and lift-off cycles.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "contact/friction_contact.h"
#include "core/types.h"
#include "hbm/aft.h"

namespace stickslip {
namespace {

constexpr int kH = 3;
constexpr int kNc = 2 * kH + 1;  // a0, (a_k, b_k)

// Steady slip on a circular orbit u_t = A (cos θ, sin θ) under constant N, derived here. Slip
// τ = μN e(φ) with φ' = kt e⊥·u_t'/(μN) (τ' = kt (u_t' − λe), |τ| = μN). u_t' = A e(θ + π/2):
// with φ = θ + π/2 − β the ODE reads 1 = kt A sin β/(μN), so the force lags the relative velocity
// by β = asin(μN/(kt A)) (constant: the steady state, stable since d/dβ(kt A sin β) > 0 there;
// needs kt A ≥ μN, else the orbit sticks). The slip rate λ = e·u_t' = A cos β > 0 never ends.
//   τ1 = −μN sin(θ − β):  a1 = μN sin β,  b1 = −μN cos β;
//   τ2 =  μN cos(θ − β):  a1 = μN cos β,  b1 =  μN sin β;  energy 2π μN A cos β.
TEST(PlanarEventAft, CircularOrbitSlipsWithTheForceLaggingTheVelocityByTheStickPhase) {
  constexpr double kTolerance = 1e-11;
  const FrictionContactParameters p{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0};
  const FrictionContact3D element(p);
  const Aft aft(FourierBasis(HarmonicSet::up_to(kH), 64), AftMethod::kEventPlanar);
  const double fs = p.mu * p.normal_preload;
  for (double A : {5.001e-5, 6e-5, 1e-4, 1e-3}) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(3 * kNc), F;
    c[0] = 2e-5;     // a mean tangential offset: irrelevant in steady slip
    c[1] = A;        // u_t1 = A cos θ
    c[kNc + 2] = A;  // u_t2 = A sin θ
    const CycleStatistics st = aft.evaluate(element, c, Eigen::VectorXd(), F, nullptr);
    EXPECT_FALSE(st.aft_fallback);
    EXPECT_NEAR(st.slip_fraction, 1.0, 1e-14);
    const double beta = std::asin(fs / (p.kt * A));
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(3 * kNc);
    expected[1] = fs * std::sin(beta);
    expected[2] = -fs * std::cos(beta);
    expected[kNc + 1] = fs * std::cos(beta);
    expected[kNc + 2] = fs * std::sin(beta);
    expected[2 * kNc] = p.normal_preload;
    EXPECT_LE((F - expected).cwiseAbs().maxCoeff(), kTolerance * fs) << "A = " << A << "\n"
                                                                     << (F - expected).transpose();
    EXPECT_NEAR(st.dissipated_energy, 2 * kPi * fs * A * std::cos(beta), kTolerance * fs * A);
  }
}

struct Case {
  std::string label;
  Eigen::VectorXd c;  // 3·nc
  bool lifts_off = false;
  bool stuck = false;  // slips in the transient from the virgin state only
};

// Elliptical tangential motion (harmonic 1 of u_t1 and u_t2 out of phase), smaller harmonics 2
// and 3, and a normal motion.
std::vector<Case> cases() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> small(-0.15, 0.15);
  auto sig = [&](double mean, double a1, double b1) {
    const double amp = std::hypot(a1, b1);
    Eigen::VectorXd s(kNc);
    s << mean, a1, b1, amp * small(rng), amp * small(rng), amp * small(rng), amp * small(rng);
    return s;
  };
  auto make = [](const Eigen::VectorXd& t1, const Eigen::VectorXd& t2, const Eigen::VectorXd& w) {
    Eigen::VectorXd c(3 * kNc);
    c << t1, t2, w;
    return c;
  };
  std::vector<Case> out;
  out.push_back({"ellipse_stick_slip", make(sig(0, 2e-4, 0), sig(0, 0, 6e-5), sig(0, 1e-5, 0))});
  out.push_back(
      {"ellipse_oblique", make(sig(1e-6, 1.5e-4, 5e-5), sig(0, -4e-5, 9e-5), sig(0, 2e-5, 1e-5))});
  out.push_back(
      {"ellipse_lift_off", make(sig(0, 1e-4, 0), sig(0, 2e-5, 6e-5), sig(0, 7e-5, 3e-5)), true});
  // A mean offset beyond the stick limit (kt·1e-4 = 2 μN): the virgin state slips at θ = 0 until
  // the motion turns, then the small ellipse (kt·1e-5 = μN/5) stays stuck on that anchor.
  out.push_back({"ellipse_stuck_after_transient",
                 make(sig(1e-4, 0, 1e-5), sig(0, 1e-5, 0), sig(0, 1e-6, 0)), false, true});
  out.push_back({"ellipse_lift_off_2",
                 make(sig(0, 6e-5, 3e-5), sig(0, -5e-5, 4e-5), sig(-1e-5, 6e-5, -5e-5)), true});
  return out;
}

const FrictionContactParameters kContact{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0};

TEST(PlanarEventAft, EllipticalCyclesAreTheSampledLawsLimit) {
  // The sampled law (radial return) converges to the continuous law at first order in 1/N (its
  // slip direction lags by O(1/N)): doubling N halves its error, and the Richardson extrapolation
  // 2 F(2N) − F(N) removes that term. At N = 16384 / 32768 the extrapolation is within
  // kRichardsonTolerance of the event forces while the raw samples are ~1e-4 off.
  constexpr double kRichardsonTolerance = 2e-6;
  const FrictionContact3D element(kContact);
  const Aft event(FourierBasis(HarmonicSet::up_to(kH), 64), AftMethod::kEventPlanar);
  const Aft coarse(FourierBasis(HarmonicSet::up_to(kH), 16384));
  const Aft fine(FourierBasis(HarmonicSet::up_to(kH), 32768));
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    Eigen::VectorXd Fe, Fc, Ff;
    const CycleStatistics st = event.evaluate(element, c.c, Eigen::VectorXd(), Fe, nullptr);
    EXPECT_FALSE(st.aft_fallback);
    EXPECT_EQ(st.slip_fraction > 0.0, !c.stuck);
    EXPECT_EQ(st.separation_fraction > 0.0, c.lifts_off);
    coarse.evaluate(element, c.c, Eigen::VectorXd(), Fc, nullptr);
    fine.evaluate(element, c.c, Eigen::VectorXd(), Ff, nullptr);
    const Eigen::VectorXd Fr = 2 * Ff - Fc;
    std::printf(
        "%s: stick %.3f slip %.3f open %.3f; sampled N = 16384 %.2e, N = 32768 %.2e, "
        "Richardson %.2e\n",
        c.label.c_str(), st.stick_fraction, st.slip_fraction, st.separation_fraction,
        (Fc - Fe).norm() / Fe.norm(), (Ff - Fe).norm() / Fe.norm(), (Fr - Fe).norm() / Fe.norm());
    EXPECT_LT((Fr - Fe).norm(), kRichardsonTolerance * Fe.norm());
    EXPECT_LT((Fr - Fe).norm(), 0.2 * (Ff - Fe).norm());
  }
}

TEST(PlanarEventAft, ForcesDoNotDependOnTheGrid) {
  // N sets only the bracketing grid and the largest step: the forces agree to round-off.
  const FrictionContact3D element(kContact);
  const Aft a(FourierBasis(HarmonicSet::up_to(kH), 32), AftMethod::kEventPlanar);
  const Aft b(FourierBasis(HarmonicSet::up_to(kH), 512), AftMethod::kEventPlanar);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    Eigen::VectorXd Fa, Fb;
    a.evaluate(element, c.c, Eigen::VectorXd(), Fa, nullptr);
    b.evaluate(element, c.c, Eigen::VectorXd(), Fb, nullptr);
    EXPECT_LT((Fa - Fb).norm(), 1e-11 * Fb.norm());
  }
}

TEST(PlanarEventAft, JacobianMatchesCentralDifferencesAtEllipticalStickSlipAndLiftOff) {
  // h = 1e-7 of the coefficient scale: O(h²) truncation and O(eps/h) round-off ≲ 1e-8 relative.
  constexpr double kFdRelativeTolerance = 1e-6;
  const FrictionContact3D element(kContact);
  const Aft aft(FourierBasis(HarmonicSet::up_to(kH), 64), AftMethod::kEventPlanar);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    Eigen::VectorXd F;
    Eigen::MatrixXd J;
    const CycleStatistics st = aft.evaluate(element, c.c, Eigen::VectorXd(), F, &J);
    EXPECT_FALSE(st.aft_fallback);
    const double h = 1e-7 * c.c.cwiseAbs().maxCoeff();
    Eigen::MatrixXd fd(J.rows(), J.cols());
    for (Eigen::Index q = 0; q < c.c.size(); ++q) {
      Eigen::VectorXd cp = c.c, cm = c.c, Fp, Fm;
      cp[q] += h;
      cm[q] -= h;
      aft.evaluate(element, cp, Eigen::VectorXd(), Fp, nullptr);
      aft.evaluate(element, cm, Eigen::VectorXd(), Fm, nullptr);
      fd.col(q) = (Fp - Fm) / (2 * h);
    }
    std::string blocks;
    for (Eigen::Index a = 0; a < 3; ++a) {
      for (Eigen::Index b = 0; b < 3; ++b) {
        blocks += " [" + std::to_string(a) + std::to_string(b) + "] " +
                  std::to_string((fd - J).block(kNc * a, kNc * b, kNc, kNc).norm()) + "/" +
                  std::to_string(J.block(kNc * a, kNc * b, kNc, kNc).norm());
      }
    }
    EXPECT_LE((fd - J).norm(), kFdRelativeTolerance * J.norm()) << blocks;
  }
}

TEST(PlanarEventAft, WarmStartedCyclesAreTheVirginMarchsCyclesInFewerPeriods) {
  // A sweep calls each pair again and again with nearby coefficients, then with the Jacobian at
  // the same ones. Started where the pair's last cycle started (aft.h, AftWarmStart), the cycle is
  // the one marched from the virgin state (the reference here, no warm start) to the closure
  // tolerance (an angle error δ moves the force by μN δ, δ ≤ 1e-13; the Jacobian by as little
  // relative to its norm), in one period when the arguments repeat (a slipping or separating
  // cycle) and at most three (two Newton steps on the start angle and the final period) nearby.
  // A start that does not apply (here: a wrong angle, a phase in stick) gives the same cycle too.
  constexpr double kForceTolerance = 1e-11;
  constexpr double kJacobianTolerance = 1e-9;
  const FrictionContact3D element(kContact);
  const Aft aft(FourierBasis(HarmonicSet::up_to(kH), 64), AftMethod::kEventPlanar);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    AftWarmStart warm;
    Eigen::VectorXd x = c.c;
    for (int call = 0; call < 6; ++call) {
      const bool jac = call % 2 == 1;  // no Jacobian at a new x, then the Jacobian at the same x
      if (!jac && call > 0) {
        for (Eigen::Index q = 0; q < x.size(); ++q) x[q] += 1e-3 * std::abs(c.c[q]) * unit(rng);
      }
      Eigen::VectorXd Fw, Fc;
      Eigen::MatrixXd Jw, Jc;
      const CycleStatistics sw =
          aft.evaluate(element, x, Eigen::VectorXd(), Fw, jac ? &Jw : nullptr, nullptr, &warm);
      const CycleStatistics sc =
          aft.evaluate(element, x, Eigen::VectorXd(), Fc, jac ? &Jc : nullptr);
      EXPECT_FALSE(sw.aft_fallback);
      EXPECT_LE((Fw - Fc).norm(), kForceTolerance * Fc.norm()) << "call " << call;
      if (jac) {
        EXPECT_LE((Jw - Jc).norm(), kJacobianTolerance * Jc.norm()) << "call " << call;
      }
      if (call > 0 && !c.stuck) {
        EXPECT_LE(sw.periods, jac ? 1 : 3) << "call " << call;
        EXPECT_LT(sw.periods, sc.periods) << "call " << call;
      }
    }
    if (c.stuck) continue;
    // A start that does not apply: the angle turned by π/2, or the phase moved to a stuck one.
    for (int variant = 0; variant < 2; ++variant) {
      AftWarmStart bad = warm;
      if (variant == 0) bad.phi += 0.5 * kPi;
      if (variant == 1) bad.theta += 0.5 * kPi;
      bad.arguments.setZero();  // other arguments: no shortcut
      Eigen::VectorXd Fw, Fc;
      aft.evaluate(element, x, Eigen::VectorXd(), Fw, nullptr, nullptr, &bad);
      aft.evaluate(element, x, Eigen::VectorXd(), Fc, nullptr);
      EXPECT_LE((Fw - Fc).norm(), kForceTolerance * Fc.norm()) << "variant " << variant;
    }
  }
}

}  // namespace
}  // namespace stickslip
