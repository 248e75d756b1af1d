// Contact laws: physical properties against hand-derived values, and one contract checker run
// against every element: the exact sample Jacobian from march() against central finite
// differences of march() itself (p = every sample value, so du_dp = I).
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../derivative_check.h"
#include "contact/friction_contact.h"
#include "contact/linear_springs.h"
#include "contact/springs.h"
#include "core/errors.h"
#include "core/types.h"

namespace stickslip {
namespace {

// u(t_j) for a closed orbit: row d = mean_d + amp_d cos(θ_j + phase_d), θ_j = 2πj/N.
Eigen::MatrixXd orbit(int n, const std::vector<double>& mean, const std::vector<double>& amp,
                      const std::vector<double>& phase) {
  const int m = static_cast<int>(mean.size());
  Eigen::MatrixXd u(m, n);
  for (int j = 0; j < n; ++j) {
    for (int d = 0; d < m; ++d) u(d, j) = mean[d] + amp[d] * std::cos(2 * kPi * j / n + phase[d]);
  }
  return u;
}

TEST(Jenkins1D, HysteresisCycleHasPlateausAndClosedFormEnergy) {
  const double kt = 1e5, mu = 0.4, n_load = 50.0;  // slip limit 20 N, x_cr = 2e-4 m
  const Jenkins1D element({.kt = kt, .mu = mu, .normal_load = n_load});
  const double x0 = 1e-3;
  const int n = 4096;
  Eigen::MatrixXd f;
  const CycleStatistics stats = element.march(orbit(n, {0.0}, {x0}, {0.0}), nullptr, f, nullptr);
  EXPECT_TRUE(stats.converged);
  EXPECT_NEAR(f.maxCoeff(), mu * n_load, 1e-12);
  EXPECT_NEAR(f.minCoeff(), -mu * n_load, 1e-12);
  // Closed form: E = 4 μN (x0 − μN/kt). The trapezoidal sum is exact except in the two samples
  // that contain a stick→slip transition: error O((2π/N)² kt x0²) ≈ 2e-6 relative at N = 4096.
  constexpr double kEnergyTolerance = 1e-5;
  const double energy = 4 * mu * n_load * (x0 - mu * n_load / kt);
  EXPECT_NEAR(stats.dissipated_energy, energy, kEnergyTolerance * energy);
  // Slip fraction: stick lasts θ_B of each half cycle, cos θ_B = 1 − 2μN/(kt x0).
  const double theta_b = std::acos(1 - 2 * mu * n_load / (kt * x0));
  EXPECT_NEAR(stats.stick_fraction, theta_b / kPi, 2.0 / n);
  EXPECT_NEAR(stats.slip_fraction, 1 - theta_b / kPi, 2.0 / n);
}

TEST(Jenkins1D, StuckCycleRepeatsInTwoPeriodsWithZeroEnergy) {
  const Jenkins1D element({.kt = 1e5, .mu = 0.4, .normal_load = 50.0});
  Eigen::MatrixXd f;
  const Eigen::MatrixXd u = orbit(64, {3e-5}, {1e-4}, {0.3});
  const CycleStatistics stats = element.march(u, nullptr, f, nullptr);
  EXPECT_EQ(stats.periods, 2);
  EXPECT_TRUE(stats.converged);
  EXPECT_DOUBLE_EQ(stats.stick_fraction, 1.0);
  EXPECT_NEAR(stats.dissipated_energy, 0.0, 1e-15);
  EXPECT_LT((f - 1e5 * u).cwiseAbs().maxCoeff(), 1e-12);  // virgin state: τ = kt u
}

TEST(FrictionContact3D, CircularLimitNotSeparateAxisClamping) {
  // Tangential motion along the diagonal in gross slip: |τ| = μN (a per-axis clamp would give
  // √2 μN), with τ parallel to the motion.
  const FrictionContactParameters p{.kt = 1e6, .kn = 1e6, .mu = 0.5, .normal_preload = 100.0};
  const FrictionContact3D element(p);
  Eigen::MatrixXd f;
  const Eigen::MatrixXd u = orbit(128, {0, 0, 0}, {1e-3, 1e-3, 0}, {0, 0, 0});
  const CycleStatistics stats = element.march(u, nullptr, f, nullptr);
  EXPECT_TRUE(stats.converged);
  double max_tau = 0;
  for (int j = 0; j < f.cols(); ++j) {
    max_tau = std::max(max_tau, f.col(j).head<2>().norm());
    EXPECT_NEAR(f(0, j), f(1, j), 1e-9);
    EXPECT_DOUBLE_EQ(f(2, j), 100.0);
  }
  EXPECT_NEAR(max_tau, 50.0, 1e-9);
  // Energy: 1D Jenkins along the diagonal with amplitude √2·1e-3.
  const double x0 = std::sqrt(2.0) * 1e-3;
  const double energy = 4 * 50.0 * (x0 - 50.0 / 1e6);
  EXPECT_NEAR(stats.dissipated_energy, energy, 2e-3 * energy);  // N = 128 trapezoid, O(1/N²)
}

TEST(FrictionContact3D, CircularOrbitSlidesWithTangentialForceOnTheCircle) {
  // u_t on a circle of radius r ≫ μN/kt: steady gross slip, |τ| = μN at every sample once the
  // cycle has converged, and the energy per cycle approaches μN · 2πr (sliding length).
  const FrictionContact3D element({.kt = 1e7, .kn = 1e6, .mu = 0.3, .normal_preload = 10.0});
  Eigen::MatrixXd f;
  const double r = 1e-3;
  const Eigen::MatrixXd u = orbit(256, {0, 0, 0}, {r, r, 0}, {0, -kPi / 2, 0});
  const CycleStatistics stats = element.march(u, nullptr, f, nullptr);
  EXPECT_TRUE(stats.converged);
  EXPECT_DOUBLE_EQ(stats.slip_fraction, 1.0);
  for (int j = 0; j < f.cols(); ++j) EXPECT_NEAR(f.col(j).head<2>().norm(), 3.0, 1e-9);
  // The chord length sum is 2πr(1 − O(1/N²)); the force lags the motion direction slightly.
  EXPECT_NEAR(stats.dissipated_energy, 3.0 * 2 * kPi * r, 1e-3 * 3.0 * 2 * kPi * r);
}

TEST(FrictionContact3D, LiftOffReleasesAllForces) {
  const double kn = 1e6, n0 = 100.0;  // contact opens for w < −1e-4
  const FrictionContact3D element({.kt = 1e6, .kn = kn, .mu = 0.5, .normal_preload = n0});
  Eigen::MatrixXd f;
  const int n = 360;
  const Eigen::MatrixXd u = orbit(n, {0, 0, 0}, {2e-5, 0, 2e-4}, {0.5, 0, 0});
  const CycleStatistics stats = element.march(u, nullptr, f, nullptr);
  int open = 0;
  for (int j = 0; j < n; ++j) {
    if (n0 + kn * u(2, j) <= 0) {
      ++open;
      EXPECT_EQ(f.col(j).norm(), 0.0);
    } else {
      EXPECT_NEAR(f(2, j), n0 + kn * u(2, j), 1e-9);
      EXPECT_LE(f.col(j).head<2>().norm(), 0.5 * f(2, j) * (1 + 1e-12));
    }
  }
  // w = 2e-4 cos θ < −1e-4 for θ in (2π/3, 4π/3): one third of the cycle.
  EXPECT_NEAR(stats.separation_fraction, 1.0 / 3.0, 2.0 / n);
  EXPECT_EQ(stats.separation_fraction, static_cast<double>(open) / n);
}

TEST(FrictionContact3D, GapClosesOnlyBeyondG0) {
  const FrictionContact3D element({.kt = 1e6, .kn = 2e6, .mu = 0.5, .gap = 1e-5});
  Eigen::MatrixXd f;
  Eigen::MatrixXd u(3, 2);
  u << 0, 0, 0, 0, 0.5e-5, 3e-5;
  element.march(u, nullptr, f, nullptr);
  EXPECT_EQ(f(2, 0), 0.0);
  EXPECT_NEAR(f(2, 1), 2e6 * 2e-5, 1e-9);
}

TEST(Springs, UnilateralAndCubicLaws) {
  const UnilateralSpring gap({.k = 1e4, .gap = 1e-3, .preload = 0.0});
  const CubicSpring cubic({.k1 = 2.0, .k3 = -5.0});
  Eigen::MatrixXd u(1, 3), f;
  u << -1e-3, 1.5e-3, 0.2;
  const CycleStatistics s = gap.march(u, nullptr, f, nullptr);
  EXPECT_EQ(f(0, 0), 0.0);
  EXPECT_NEAR(f(0, 1), 5.0, 1e-12);
  EXPECT_NEAR(s.separation_fraction, 1.0 / 3.0, 1e-15);
  cubic.march(u, nullptr, f, nullptr);
  EXPECT_NEAR(f(0, 2), 2.0 * 0.2 - 5.0 * 0.008, 1e-15);
}

TEST(LinearSprings, ForceIsDiagonalStiffnessTimesDisplacementWithoutDissipation) {
  const Eigen::Vector3d k(2.0e8, 2.0e8, 5.0e8);
  const LinearSprings springs(k);
  ASSERT_EQ(springs.dimension(), 3);
  const Eigen::MatrixXd u = orbit(16, {1e-7, 0, -2e-7}, {1e-6, 2e-6, 5e-7}, {0.2, 1.3, 0.1});
  Eigen::MatrixXd f;
  const CycleStatistics stats = springs.march(u, nullptr, f, nullptr);
  EXPECT_EQ(stats.stick_fraction, 1.0);
  EXPECT_EQ(stats.dissipated_energy, 0.0);
  for (int j = 0; j < u.cols(); ++j) {
    for (int d = 0; d < 3; ++d) EXPECT_DOUBLE_EQ(f(d, j), k(d) * u(d, j));
  }
  EXPECT_THROW(springs.march(Eigen::MatrixXd::Zero(2, 16), nullptr, f, nullptr), InvalidInput);
  EXPECT_THROW(LinearSprings(Eigen::VectorXd()), InvalidInput);
  EXPECT_THROW(LinearSprings(Eigen::Vector2d(1.0, -1.0)), InvalidInput);
}

TEST(Elements, InvalidParametersThrow) {
  EXPECT_THROW(FrictionContact3D({.kt = -1, .kn = 1, .mu = 0.1}), InvalidInput);
  EXPECT_THROW(FrictionContact3D({.kt = 1, .kn = 1, .mu = -0.1}), InvalidInput);
  EXPECT_THROW(Jenkins1D({.kt = 1, .mu = 0.1, .normal_load = -2}), InvalidInput);
  EXPECT_THROW(UnilateralSpring({.k = 0}), InvalidInput);
  EXPECT_THROW(CubicSpring({.k1 = 1, .k3 = std::nan("")}), InvalidInput);
  EXPECT_THROW(Jenkins1D({.kt = 1, .mu = 0.1, .normal_load = 1}, {.max_periods = 1}), InvalidInput);
}

TEST(Elements, MessagesQuoteTheOffendingValueExactly) {
  // core/format.h: std::to_string would have quoted −1e-9 as "-0.000000".
  auto message = [](auto&& make) {
    try {
      make();
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message([] { UnilateralSpring({.k = -1e-9}); }).find("-1e-09"), std::string::npos);
  EXPECT_NE(message([] { Jenkins1D({.kt = 1, .mu = -2.5e-7, .normal_load = 1}); }).find("-2.5e-07"),
            std::string::npos);
}

// ---- Contract checker: exact sample Jacobian vs central differences, for every element. ----

struct Case {
  std::string label;
  std::shared_ptr<const NonlinearElement> element;
  Eigen::MatrixXd u;
};

std::vector<Case> contract_cases() {
  const int n = 24;
  std::vector<Case> cases;
  const FrictionContactParameters fc{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0};
  auto contact = std::make_shared<FrictionContact3D>(fc);
  cases.push_back({"3d_stick", contact, orbit(n, {1e-6, 0, 0}, {1e-5, 2e-5, 1e-6}, {0, 1, 2})});
  cases.push_back({"3d_slip", contact, orbit(n, {0, 0, 0}, {3e-4, 2e-4, 1e-5}, {0, 1.1, 0.4})});
  // Small slip in 2D against a large stick range: plain marching closes this cycle only slowly.
  cases.push_back(
      {"3d_partial_slip", contact, orbit(n, {0, 0, 0}, {5.25e-5, 2e-5, 1e-6}, {0, 1.5708, 0.3})});
  cases.push_back(
      {"3d_liftoff_mixed", contact, orbit(n, {0, 0, 1e-6}, {1e-4, 5e-5, 9e-5}, {0.2, 1.3, 0.1})});
  auto gap_contact = std::make_shared<FrictionContact3D>(
      FrictionContactParameters{.kt = 1e6, .kn = 2e6, .mu = 0.3, .gap = 1e-5});
  cases.push_back(
      {"3d_gap", gap_contact, orbit(n, {0, 0, 2e-5}, {1e-5, 5e-6, 3e-5}, {0.2, 1.3, 0.1})});
  auto jenkins =
      std::make_shared<Jenkins1D>(JenkinsParameters{.kt = 1e5, .mu = 0.4, .normal_load = 50});
  cases.push_back({"jenkins_stick", jenkins, orbit(n, {1e-5}, {5e-5}, {0.3})});
  cases.push_back({"jenkins_slip", jenkins, orbit(n, {1e-5}, {1e-3}, {0.3})});
  auto gap = std::make_shared<UnilateralSpring>(UnilateralSpringParameters{.k = 1e4, .gap = 1e-3});
  cases.push_back({"unilateral", gap, orbit(n, {1e-3}, {2e-3}, {0.3})});
  auto cubic = std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = 1e3, .k3 = 1e9});
  cases.push_back({"cubic", cubic, orbit(n, {1e-4}, {1e-3}, {0.3})});
  cases.push_back({"linear_springs", make_linear_springs(Eigen::Vector3d(2e8, 2e8, 5e8)),
                   orbit(n, {1e-7, 0, -2e-7}, {1e-6, 2e-6, 5e-7}, {0.2, 1.3, 0.1})});
  return cases;
}

TEST(ElementContract, SampleJacobianMatchesCentralDifferences) {
  // h = 1e-6 of the signal scale: FD error O(h²)·|f''| + O(eps·|f|/h) ~ 1e-9 relative; a sample
  // that crosses a stick/slip/contact boundary within ±h would spoil it (none does here: the
  // orbits are generic and each case's regime counts are checked unchanged below).
  constexpr double kFdRelativeTolerance = 1e-6;
  for (const Case& c : contract_cases()) {
    SCOPED_TRACE(c.label);
    const int m = static_cast<int>(c.u.rows()), n = static_cast<int>(c.u.cols());
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(m * n, m * n);
    Eigen::MatrixXd f, df;
    const CycleStatistics s0 = c.element->march(c.u, &identity, f, &df);
    EXPECT_TRUE(s0.converged);
    const double scale = c.u.cwiseAbs().maxCoeff();
    const double h = 1e-6 * scale;
    Eigen::MatrixXd fd(m * n, m * n);
    for (int q = 0; q < m * n; ++q) {
      Eigen::MatrixXd up = c.u, um = c.u, fp, fm;
      up(q % m, q / m) += h;
      um(q % m, q / m) -= h;
      c.element->march(up, nullptr, fp, nullptr);
      c.element->march(um, nullptr, fm, nullptr);
      fd.col(q) = Eigen::Map<Eigen::VectorXd>(Eigen::MatrixXd((fp - fm) / (2 * h)).data(), m * n);
    }
    EXPECT_LE((fd - df).norm(), kFdRelativeTolerance * df.norm())
        << "exact\n"
        << df.topLeftCorner(6, 6) << "\nfd\n"
        << fd.topLeftCorner(6, 6);
  }
}

TEST(ElementContract, SampleJacobianPassesTheTaylorCheck) {
  // tests/derivative_check.h: along a random direction of the orbit's size the remainder of the
  // exact sample derivative falls like h² (or is round-off on linear branches: stick, open).
  std::mt19937 rng(17);
  std::normal_distribution<double> normal;
  for (const Case& c : contract_cases()) {
    SCOPED_TRACE(c.label);
    Eigen::MatrixXd du(c.u.rows(), c.u.cols());
    for (Eigen::Index i = 0; i < du.size(); ++i) du.data()[i] = normal(rng);
    du *= c.u.norm() / du.norm();
    testing::expect_taylor_slope(testing::taylor_remainder(*c.element, c.u, du));
  }
}

// The law of the header marched plainly, period after period from the virgin state, written out
// here independently of the element: the reference the element's periodic cycle must equal.
Eigen::MatrixXd plain_march(const FrictionContactParameters& p, const Eigen::MatrixXd& u,
                            int periods) {
  const int n = static_cast<int>(u.cols());
  Eigen::MatrixXd f(3, n);
  Eigen::Vector2d tau(0, 0), prev(0, 0);
  for (int k = 0; k < periods; ++k) {
    for (int j = 0; j < n; ++j) {
      const double normal = std::max(0.0, p.normal_preload + p.kn * (u(2, j) - p.gap));
      const Eigen::Vector2d ut = u.col(j).head<2>();
      Eigen::Vector2d pred = tau + p.kt * (ut - prev);
      if (normal == 0.0) pred.setZero();
      if (pred.norm() > p.mu * normal) pred *= p.mu * normal / pred.norm();
      tau = pred;
      prev = ut;
      f.col(j) << tau, normal;
    }
  }
  return f;
}

TEST(FrictionContact3D, PartialSlipCycleIsTheLimitOfPlainMarchingInFewPeriods) {
  // Slip of ~5% of the stick range along an ellipse: each slip phase contracts the start state
  // by only a few per cent, so plain marching needs hundreds of periods to close to 1e-12; the
  // element solves the periodicity condition instead and must give the same cycle.
  const FrictionContactParameters fc{.kt = 1e6, .kn = 2e6, .mu = 0.5, .normal_preload = 100.0};
  const FrictionContact3D contact(fc);
  const Eigen::MatrixXd u = orbit(64, {0, 0, 0}, {5.25e-5, 2e-5, 1e-6}, {0, 1.5708, 0.3});
  Eigen::MatrixXd f;
  const CycleStatistics s = contact.march(u, nullptr, f, nullptr);
  EXPECT_TRUE(s.converged);
  EXPECT_GT(s.slip_fraction, 0.0);
  constexpr int kFewPeriods = 10;  // periods 1-2 plus a handful of Newton iterations
  EXPECT_LE(s.periods, kFewPeriods);
  const Eigen::MatrixXd reference = plain_march(fc, u, 20000);
  // The plain march after 20000 periods is closed to round-off; 1e-9 of μN allows for it.
  constexpr double kCycleTolerance = 1e-9;
  EXPECT_LE((f - reference).cwiseAbs().maxCoeff(), kCycleTolerance * fc.mu * fc.normal_preload);
  // The plain march stopped early is still far from it: the case does test the slow closure.
  EXPECT_GT((plain_march(fc, u, 10) - reference).cwiseAbs().maxCoeff(),
            1e-5 * fc.mu * fc.normal_preload);
}

TEST(ElementContract, CasesCoverEveryRegime) {
  Eigen::MatrixXd f;
  for (const Case& c : contract_cases()) {
    const CycleStatistics s = c.element->march(c.u, nullptr, f, nullptr);
    if (c.label == "3d_stick" || c.label == "jenkins_stick") {
      EXPECT_EQ(s.stick_fraction, 1.0);
    }
    if (c.label == "3d_slip" || c.label == "jenkins_slip") {
      EXPECT_GT(s.slip_fraction, 0.3);
    }
    if (c.label == "3d_partial_slip") {
      EXPECT_GT(s.slip_fraction, 0.0);
      EXPECT_GT(s.stick_fraction, 0.5);
    }
    if (c.label == "3d_liftoff_mixed" || c.label == "3d_gap") {
      EXPECT_GT(s.separation_fraction, 0.1) << c.label;
      EXPECT_GT(s.slip_fraction, 0.0) << c.label;
      EXPECT_GT(s.stick_fraction, 0.0) << c.label;
    }
    if (c.label == "unilateral") {
      EXPECT_GT(s.separation_fraction, 0.1);
    }
  }
}

}  // namespace
}  // namespace stickslip
