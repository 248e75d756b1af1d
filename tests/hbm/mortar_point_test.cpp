// A mortar contact point in the harmonic balance (issue 23, item 4): its relative displacement
// is u = R (x_A − Φ_1 x_B1 − Φ_2 x_B2), i.e. a ContactPair whose dofs_a hold node A's and both B
// nodes' DOFs and whose frame is R [I, −Φ_1 I, −Φ_2 I] (model/case_model.h, PreparedPair). The
// harmonic balance takes it like any pair: its Jacobians against central differences over a
// cycle with stick, slip and lift-off, and its stuck limit against the linear FRF solved
// directly with the same map.
#include "hbm/harmonic_balance.h"

#include <complex>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "hbm/frequency_response.h"
#include "hbm_test_support.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

constexpr double kPhi1 = 0.35, kPhi2 = 0.65;  // the point's weights on B's two nodes

// Three 3D nodes (A, B1, B2) on ground springs with a little structural coupling; the point
// joins A to B1 and B2.
struct ThreeNodes {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(9, 9), M = Eigen::MatrixXd::Zero(9, 9);
  double alpha = 2.0, beta = 1e-5;
  Eigen::Matrix3d R;
  Eigen::MatrixXd frame;  // 3 x 9: R [I, −Φ_1 I, −Φ_2 I]
  Eigen::VectorXcd load1 = Eigen::VectorXcd::Zero(9);
};

ThreeNodes three_nodes() {
  ThreeNodes s;
  const double k[9] = {1e4, 2e4, 1.5e4, 1.2e4, 0.8e4, 2.5e4, 1.1e4, 1.7e4, 0.9e4};
  const double m[9] = {1.0, 1.0, 1.0, 1.5, 1.5, 1.5, 0.8, 0.8, 0.8};
  for (int i = 0; i < 9; ++i) {
    s.K(i, i) = k[i];
    s.M(i, i) = m[i];
  }
  s.K(0, 3) = s.K(3, 0) = -2e3;
  s.K(4, 7) = s.K(7, 4) = -1e3;  // B1 and B2 coupled, as neighbours on B's surface
  s.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  s.frame.resize(3, 9);
  s.frame << s.R, -kPhi1 * s.R, -kPhi2 * s.R;
  s.load1 << Complex(3, 1), Complex(-2, 0), Complex(1, 2), 0, Complex(0.5, 0), 0, Complex(0, 1), 0,
      Complex(-1, 0);
  return s;
}

ContactPair mortar_point(const ThreeNodes& s, const FrictionContactParameters& p) {
  return {.dofs_a = {0, 1, 2, 3, 4, 5, 6, 7, 8},
          .dofs_b = {},
          .frame = s.frame,
          .element = std::make_shared<FrictionContact3D>(p)};
}

TEST(MortarPoint, JacobiansMatchFiniteDifferences) {
  // Central differences with h = 1e-7 of the unknowns' scale: truncation and round-off ≲ 1e-8
  // relative (as harmonic_balance_test's).
  constexpr double kFdRelativeTolerance = 1e-6;
  const ThreeNodes s = three_nodes();
  const FrictionContactParameters contact{.kt = 3e4, .kn = 5e4, .mu = 0.4, .normal_preload = 20.0};
  for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
    Excitation e;
    e.harmonics[1] = s.load1;
    HarmonicBalanceOptions o;
    o.harmonics = 2;
    o.time_samples = 32;
    o.static_coupling = coupling;
    const HarmonicBalanceSystem sys(linear_model_from_matrices(s.K, s.M, s.alpha, s.beta),
                                    {mortar_point(s, contact)}, e, o);
    ASSERT_TRUE(sys.static_summary().converged());
    const Eigen::VectorXd x = testing::random_state(sys.size(), 6e-4, 5);  // ~ lift-off amplitude
    testing::expect_derivatives_match_central_differences(sys, x, 110.0, 1e-7 * 6e-4,
                                                          kFdRelativeTolerance);
    testing::expect_first_pair_slips_and_separates(sys, x);
  }
}

// With friction that never slips (μ huge) and a preload that keeps the point closed, the point
// is the linear spring diag(kt, kt, kn) on u = B x, B = the frame: the harmonic balance's
// response of every DOF is the direct solve of (K + BᵀKcB − Ω² M + iΩC) x = F.
TEST(MortarPoint, StuckPointGivesTheLinearFrfOfItsMap) {
  constexpr double kTolerance = 1e-9;  // Newton at 1e-12 on a linear problem
  const ThreeNodes s = three_nodes();
  const FrictionContactParameters stuck{.kt = 3e4, .kn = 5e4, .mu = 1e6, .normal_preload = 1e3};
  Excitation e;
  e.harmonics[1] = s.load1;
  HarmonicBalanceOptions o;
  o.harmonics = 1;
  o.time_samples = 32;
  const HarmonicBalanceSystem sys(linear_model_from_matrices(s.K, s.M, s.alpha, s.beta),
                                  {mortar_point(s, stuck)}, e, o);
  FrequencyResponseOptions fo;
  fo.method = ContinuationMethod::kSteppedSweep;
  fo.omegas = {90.0, 130.0};
  fo.sweep.newton.tolerance = 1e-12;
  const FrequencyResponse fr = frequency_response(sys, fo);
  const Eigen::MatrixXd Kc =
      s.frame.transpose() * Eigen::Vector3d(3e4, 3e4, 5e4).asDiagonal() * s.frame;
  const Eigen::MatrixXd C = s.alpha * s.M + s.beta * s.K;
  ASSERT_EQ(fr.points.size(), 2u);
  for (const FrequencyPoint& p : fr.points) {
    ASSERT_TRUE(p.converged);
    const double w = p.omega;
    const Eigen::MatrixXcd D =
        (s.K + Kc - w * w * s.M).cast<Complex>() + Complex(0, w) * C.cast<Complex>();
    const Eigen::VectorXcd x = D.partialPivLu().solve(s.load1);
    // Harmonic 1 is column 1 of master (harmonics 0, 1).
    EXPECT_LT((p.master.col(1) - x).norm(), kTolerance * x.norm()) << w;
  }
}

}  // namespace
}  // namespace stickslip
