// The structured Newton solve of HarmonicBalanceSystem (GMRES on I + 𝔾 J_f preconditioned at the
// stuck state) against the dense path: the same linear solves (dense LU of the dense dR/dx as the
// reference), the same Newton iterates, the same stuck linear guess, on a small case with several
// 3D friction pairs in partial slip, coupled and uncoupled statics, H = 2.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {
namespace {

// GMRES stops at 1e-10 relative residual; the Jacobians here have condition numbers ≲ 1e3, so
// the structured step agrees with the LU step to ≲ 1e-7 relative (we allow 1e-6).
constexpr double kStepAgreement = 1e-6;
// Newton iterates built from such steps agree to the same order while the iteration converges.
constexpr double kIterateAgreement = 1e-6;

constexpr int kNodes = 6;  // per body
constexpr int kPairs = 4;  // the last kPairs nodes of each chain

HarmonicBalanceSystem make_chains(StaticCoupling coupling, HbmLinearSolver solver) {
  const int n = 2 * kNodes * 3;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), M = Eigen::MatrixXd::Zero(n, n);
  const double k_chain[3] = {4e4, 2e4, 3e4};
  for (int b = 0; b < 2; ++b) {
    for (int i = 0; i < kNodes; ++i) {
      for (int d = 0; d < 3; ++d) {
        const int p = 3 * (b * kNodes + i) + d;
        M(p, p) = 1.0 + 0.1 * i + 0.05 * b;
        if (i == 0) K(p, p) += 10 * k_chain[d];
        if (i + 1 < kNodes) {
          const double k = k_chain[d] * (1.0 + 0.2 * ((i * 7 + d + b) % 5));
          K(p, p) += k;
          K(p + 3, p + 3) += k;
          K(p, p + 3) -= k;
          K(p + 3, p) -= k;
        }
      }
    }
  }
  std::vector<ContactPair> pairs;
  for (int q = 0; q < kPairs; ++q) {
    const int a = kNodes - kPairs + q, b = kNodes + a;
    const FrictionContactParameters c{
        .kt = 2e5, .kn = 3e5, .mu = 0.4, .normal_preload = 5.0 + 3.0 * q};
    pairs.push_back(
        {.dofs_a = {3 * a, 3 * a + 1, 3 * a + 2},
         .dofs_b = {3 * b, 3 * b + 1, 3 * b + 2},
         .frame = Eigen::AngleAxisd(0.1 * q, Eigen::Vector3d(0, 0, 1)).toRotationMatrix(),
         .element = std::make_shared<FrictionContact3D>(c)});
  }
  Excitation e;
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  f[3 * (kNodes - 1)] = 3.0;
  f[3 * (kNodes - 1) + 1] = std::complex<double>(0, 1.0);
  f[3 * (2 * kNodes - 1)] = -2.0;
  e.harmonics[1] = f;
  HarmonicBalanceOptions o;
  o.harmonics = 2;
  o.time_samples = 32;
  o.static_coupling = coupling;
  o.static_newton.tolerance = 1e-12;
  o.linear_solver = solver;
  return HarmonicBalanceSystem(linear_model_from_matrices(K, M, 2.0, 1e-5), pairs, e, o);
}

TEST(StructuredSolve, MatchesDenseLuAndDenseNewton) {
  for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
    const HarmonicBalanceSystem dense = make_chains(coupling, HbmLinearSolver::kDense);
    const HarmonicBalanceSystem structured = make_chains(coupling, HbmLinearSolver::kStructured);
    ASSERT_FALSE(dense.has_structured_jacobian());
    ASSERT_TRUE(structured.has_structured_jacobian());
    ASSERT_TRUE(dense.static_summary().converged());
    bool any_slip = false;
    // Near the first stuck resonance of the chains, where the load makes the pairs slip.
    for (double omega : {60.0, 95.0, 130.0}) {
      // The stuck guess: exact solve with the stuck tangent in both paths.
      const Eigen::VectorXd g_dense = dense.linear_guess(omega, true);
      const Eigen::VectorXd g_struct = structured.linear_guess(omega, true);
      EXPECT_LE((g_struct - g_dense).norm(), kStepAgreement * g_dense.norm());

      // One linear solve at a slipping state (random around the guess): dense LU as reference.
      std::mt19937 rng(5);
      std::uniform_real_distribution<double> u(0.5, 1.5);
      Eigen::VectorXd x = g_dense;
      for (Eigen::Index i = 0; i < x.size(); ++i) x[i] *= u(rng);
      Eigen::VectorXd R;
      Eigen::MatrixXd J;
      dense.evaluate(x, omega, R, &J, nullptr);
      const Eigen::VectorXd step_lu = J.partialPivLu().solve(-R);
      Eigen::VectorXd step;
      ASSERT_TRUE(structured.solve_jacobian(x, omega, -R, step));
      EXPECT_LE((step - step_lu).norm(), kStepAgreement * step_lu.norm());

      // Newton from the guess: the same iterates (textbook steps: the structured solve takes no
      // chord steps).
      NewtonOptions o;
      o.tolerance = 1e-10;
      o.max_iterations = 60;
      o.reuse_jacobian = false;
      Eigen::VectorXd xd = g_dense, xs = g_dense;
      const NewtonSummary sd = solve_newton(dense, omega, xd, o);
      const NewtonSummary ss = solve_newton(structured, omega, xs, o);
      ASSERT_TRUE(sd.converged()) << sd.message;
      ASSERT_TRUE(ss.converged()) << ss.message;
      EXPECT_EQ(sd.iterations, ss.iterations);
      EXPECT_LE((xs - xd).norm(), kIterateAgreement * xd.norm());
      // The solution is not trivially stuck: some pair slips (the preconditioner is not exact).
      Eigen::VectorXd F;
      std::vector<CycleStatistics> stats;
      dense.contact_forces(xd, F, &stats);
      double slip = 0;
      for (const CycleStatistics& s : stats) slip = std::max(slip, s.slip_fraction);
      if (slip > 0) {
        any_slip = true;
        EXPECT_GT(structured.last_gmres_iterations(), 1);
      }
    }
    EXPECT_TRUE(any_slip);
  }
}

TEST(StructuredSolve, SteppedSweepHasNoDenseArcLengthFallback) {
  // Newton allowed one step per point: points fail. The dense system may follow the curve by
  // arc-length (dense dR/dx); the structured one must not, and its message says so.
  const HarmonicBalanceSystem dense =
      make_chains(StaticCoupling::kUncoupled, HbmLinearSolver::kDense);
  const HarmonicBalanceSystem structured =
      make_chains(StaticCoupling::kUncoupled, HbmLinearSolver::kStructured);
  FrequencyResponseOptions o;
  for (int i = 0; i <= 5; ++i) o.omegas.push_back(60.0 + 14.0 * i);
  o.sweep.newton.max_iterations = 1;
  o.sweep.max_step_halvings = 0;
  const FrequencyResponse s = frequency_response(structured, o);
  ASSERT_FALSE(s.completed) << s.message;
  EXPECT_NE(s.message.find("no arc-length fallback"), std::string::npos) << s.message;
  const FrequencyResponse d = frequency_response(dense, o);
  EXPECT_EQ(d.message.find("no arc-length fallback"), std::string::npos) << d.message;
}

}  // namespace
}  // namespace stickslip
