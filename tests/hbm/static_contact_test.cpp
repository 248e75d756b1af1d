// The static contact problem of `static: uncoupled` (HarmonicBalanceSystem::solve_static) for a
// contact without a preload pressed by a static load (preload: computed): one node on ground
// springs k_s in x, y, z, touching the ground through a friction contact (kt, kn, μ, N0 = 0;
// frame rows x, y, z: the normal is z), loaded by F along +z (pressing) and T along x. Closed
// form: N = kn F / (k_s + kn); stuck τ = kt T / (k_s + kt) while that is ≤ μN, else slip with
// τ = μN and x = (T − μN) / k_s. kn = 1000 k_s: from rest (open tangent at the kink w = 0) the
// first Newton step goes to the response without the contact and no fraction of it decreases ‖R‖;
// the solve must still converge (it restarts from the linear response).
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "contact/friction_contact.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {
namespace {

constexpr double kTolerance = 1e-9;  // relative; Newton converges to 1e-8 of ‖u_lin,0‖ and the
                                     // last (exact, piecewise linear) step lands to round-off

struct Result {
  Eigen::Vector3d u, f;
  bool converged;
};

Result solve(double ks, double kt, double kn, double mu, double F, double T) {
  const Eigen::Matrix3d K = ks * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  const LinearModel model = linear_model_from_matrices(K, M, 1.0, 0.0);
  ContactPair pair{.dofs_a = {0, 1, 2},
                   .dofs_b = {},
                   .frame = Eigen::MatrixXd::Identity(3, 3),
                   .element = std::make_shared<FrictionContact3D>(
                       FrictionContactParameters{kt, kn, mu, 0.0, 0.0})};
  Excitation e;
  e.harmonics[0] = Eigen::VectorXcd::Zero(3);
  e.harmonics[0](0) = T;
  e.harmonics[0](2) = F;
  e.harmonics[1] = Eigen::VectorXcd::Zero(3);
  e.harmonics[1](0) = 1e-3;
  HarmonicBalanceOptions opt;
  opt.time_samples = 16;
  const HarmonicBalanceSystem sys(model, {pair}, e, opt);
  return {sys.static_displacement(), sys.static_force(), sys.static_summary().converged()};
}

TEST(StaticContact, PressedContactWithoutPreloadSticksOrSlipsAsTheClosedFormSays) {
  const double ks = 1.0e6, kt = 5.0e8, kn = 1.0e9, mu = 0.5, F = 1000.0;
  const double N = kn * F / (ks + kn);
  for (const double T : {100.0, 2000.0}) {
    const Result r = solve(ks, kt, kn, mu, F, T);
    ASSERT_TRUE(r.converged) << "T = " << T;
    const double stuck = kt * T / (ks + kt);
    const bool slips = stuck > mu * N;
    const double tau = slips ? mu * N : stuck;
    const double x = slips ? (T - mu * N) / ks : T / (ks + kt);
    EXPECT_EQ(slips, T > 1000.0);
    EXPECT_NEAR(r.f(2), N, kTolerance * N) << T;
    EXPECT_NEAR(r.u(2), F / (ks + kn), kTolerance * F / (ks + kn)) << T;
    EXPECT_NEAR(r.f(0), tau, kTolerance * N) << T;
    EXPECT_NEAR(r.u(0), x, kTolerance * std::abs(x)) << T;
    EXPECT_NEAR(r.f(1), 0.0, kTolerance * N) << T;
  }
}

TEST(StaticContact, ALoadPullingTheContactOpenLeavesItOpenAndForceFree) {
  const double ks = 1.0e6, F = -1000.0, T = 300.0;
  const Result r = solve(ks, 5.0e8, 1.0e9, 0.5, F, T);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.f.norm(), 0.0);
  EXPECT_NEAR(r.u(2), F / ks, kTolerance * std::abs(F / ks));
  EXPECT_NEAR(r.u(0), T / ks, kTolerance * T / ks);
}

// The load-incremental static path (harmonic_balance.h, "Static loading path") against a hand
// calculation: the same node on springs k_s touches the ground through two friction contacts
// (kt, kn, μ each) with initial gaps g1 < g2, and the static load λ (Q along x, P pressing along
// z) grows from 0 to 1. Contact 1 closes at λ1 = g1 k_s / P, while the node has moved by
// a1 = λ1 Q / k_s along x: its tangential spring starts there. Then x = (λQ + kt a1)/(k_s + kt)
// and z = (λP + kn g1)/(k_s + kn) until contact 2 closes at λ2 = (g2 (k_s + kn) − kn g1) / P,
// at x = a2; at λ = 1, x = (Q + kt (a1 + a2))/(k_s + 2 kt), z = (P + kn (g1 + g2))/(k_s + 2 kn),
// τ_i = kt (x − a_i), N_i = kn (z − g_i), both stuck (checked: after each touchdown the stuck
// tangential force grows slower than μ times the normal force, and |τ_i| ≤ μN_i at the ends of
// the phases, between which both are linear in λ): τ = 102, 51 N. One proportional
// step instead (static_increments: 1) starts both springs at x = 0: stuck both would give
// τ = kt Q/(k_s + 2 kt) each, beyond contact 2's limit, so contact 2 slips, τ2 = μN2 and
// τ1 = kt (Q − μN2)/(k_s + kt): 107.5, 85 N, 67 % more force on contact 2 than the path's.
// The touchdowns λ1 = 0.15, λ2 = 0.49 fall inside steps (10 automatic, or 3): each is cut there,
// so the path is exact whatever the steps. And the harmonic balance starts from that state: a
// cycle without vibration (x = 0) marches the static τ_i (a virgin march at u0 would give
// kt x for both).
TEST(StaticContact, TwoContactsClosingInSequenceFollowTheLoadPath) {
  const double ks = 1.0e6, kt = 1.0e6, kn = 1.0e6, mu = 0.5, P = 1000.0, Q = 300.0;
  const double g1 = 1.5e-4, g2 = 3.2e-4;
  // The hand calculation.
  const double l1 = g1 * ks / P, a1 = l1 * Q / ks;
  const double l2 = (g2 * (ks + kn) - kn * g1) / P, a2 = (l2 * Q + kt * a1) / (ks + kt);
  const double x = (Q + kt * (a1 + a2)) / (ks + 2 * kt), z = (P + kn * (g1 + g2)) / (ks + 2 * kn);
  const double tau1 = kt * (x - a1), tau2 = kt * (x - a2), N1 = kn * (z - g1), N2 = kn * (z - g2);
  ASSERT_LT(kt * Q / (ks + kt), mu * kn * P / (ks + kn));          // contact 1 after λ1
  ASSERT_LT(kt * Q / (ks + 2 * kt), mu * kn * P / (ks + 2 * kn));  // contact 2 after λ2
  ASSERT_LT(kt * (a2 - a1), mu * kn * (g2 - g1));                  // contact 1 at λ2
  ASSERT_LT(tau1, mu * N1);
  ASSERT_LT(tau2, mu * N2);
  ASSERT_GT(l1, 0.1);
  ASSERT_LT(l2, 0.5);
  // One step: contact 2 slips.
  const double tau2_one = mu * N2, tau1_one = kt * (Q - tau2_one) / (ks + kt);
  ASSERT_GT(kt * Q / (ks + 2 * kt), mu * N2);
  ASSERT_LT(tau1_one, mu * N1);

  for (const StaticCoupling coupling : {StaticCoupling::kUncoupled, StaticCoupling::kCoupled}) {
    for (const int increments : {0, 3, 1}) {
      SCOPED_TRACE(testing::Message() << "increments " << increments << ", coupled "
                                      << (coupling == StaticCoupling::kCoupled));
      const LinearModel model = linear_model_from_matrices(ks * Eigen::Matrix3d::Identity(),
                                                           Eigen::Matrix3d::Identity(), 1.0, 0.0);
      std::vector<ContactPair> pairs;
      for (const double g : {g1, g2}) {
        pairs.push_back({.dofs_a = {0, 1, 2},
                         .dofs_b = {},
                         .frame = Eigen::MatrixXd::Identity(3, 3),
                         .element = std::make_shared<FrictionContact3D>(
                             FrictionContactParameters{kt, kn, mu, 0.0, g})});
      }
      Excitation e;
      e.harmonics[0] = Eigen::VectorXcd::Zero(3);
      e.harmonics[0](0) = Q;
      e.harmonics[0](2) = P;
      e.harmonics[1] = Eigen::VectorXcd::Zero(3);
      e.harmonics[1](1) = 1e-3;
      HarmonicBalanceOptions opt;
      opt.time_samples = 16;
      opt.static_coupling = coupling;
      opt.static_increments = increments;
      const HarmonicBalanceSystem sys(model, pairs, e, opt);
      ASSERT_TRUE(sys.static_summary().converged()) << sys.static_summary().message;
      const Eigen::VectorXd& f = sys.static_force();
      const bool one_step = increments == 1;
      EXPECT_EQ(sys.static_path().touchdown_cuts, one_step ? 0 : 2);
      EXPECT_EQ(sys.static_path().steps, one_step ? 1 : (increments == 0 ? 10 : 3) + 2);
      EXPECT_NEAR(f(2), N1, kTolerance * P);
      EXPECT_NEAR(f(5), N2, kTolerance * P);
      EXPECT_NEAR(f(0), one_step ? tau1_one : tau1, kTolerance * P);
      EXPECT_NEAR(f(3), one_step ? tau2_one : tau2, kTolerance * P);
      EXPECT_NEAR(f(1), 0.0, kTolerance * P);
      EXPECT_NEAR(f(4), 0.0, kTolerance * P);
      // A cycle without vibration marches the static state.
      Eigen::VectorXd still = Eigen::VectorXd::Zero(sys.size());
      if (coupling == StaticCoupling::kCoupled) {
        const int nc = sys.unknown_harmonics().coefficient_count();
        for (int r = 0; r < 6; ++r) still[r * nc] = sys.static_displacement()[r];
      }
      for (int p = 0; p < 2; ++p) {
        const AftSamples cycle = sys.pair_cycle(still, p);
        for (int j = 0; j < cycle.f.cols(); ++j) {
          EXPECT_NEAR((cycle.f.col(j) - f.segment(3 * p, 3)).norm(), 0.0, kTolerance * P) << p;
          EXPECT_NEAR((cycle.u.col(j) - sys.static_displacement().segment(3 * p, 3)).norm(), 0.0,
                      kTolerance * z)
              << p;
        }
      }
    }
  }
  std::printf("[ hand calculation ] incremental tau = %.6g, %.6g N; one step %.6g, %.6g N\n", tau1,
              tau2, tau1_one, tau2_one);
}

}  // namespace
}  // namespace stickslip
