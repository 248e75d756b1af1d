// The static contact problem of `static: uncoupled` (HarmonicBalanceSystem::solve_static) for a
// contact without a preload pressed by a static load (preload: computed): one node on ground
// springs k_s in x, y, z, touching the ground through a friction contact (kt, kn, μ, N0 = 0;
// frame rows x, y, z: the normal is z), loaded by F along +z (pressing) and T along x. Closed
// form: N = kn F / (k_s + kn); stuck τ = kt T / (k_s + kt) while that is ≤ μN, else slip with
// τ = μN and x = (T − μN) / k_s. kn = 1000 k_s: from rest (open tangent at the kink w = 0) the
// first Newton step goes to the response without the contact and no fraction of it decreases ‖R‖;
// the solve must still converge (it restarts from the linear response).
#include <gtest/gtest.h>

#include <memory>

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

}  // namespace
}  // namespace stickslip
