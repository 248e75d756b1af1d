// The low-rank structured solve of HarmonicBalanceSystem (HbmLinearSolver::kLowRank: G_k applied
// through the modes, never formed; the stuck preconditioner and the static Newton steps by
// Woodbury over the modes) on a truncated modal model (fewer modes than contact rows), against
// the dense path on the same model: the residual, the static state, a linear solve against the
// dense LU and against central differences of the residual, the stuck guess, Newton's iterates
// and a short sweep; coupled and uncoupled statics, diagonal and dense modal damping, H = 2.
#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "core/errors.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {
namespace {

// GMRES and the Woodbury solves stop at or near round-off; the Jacobians here have condition
// numbers ≲ 1e3, so the steps agree with the dense LU's to ≲ 1e-8 relative (we allow 1e-6, as
// tests/hbm/structured_solve_test.cpp does).
constexpr double kStepAgreement = 1e-6;
constexpr double kIterateAgreement = 1e-6;
// The residual and the static state: the same products in another order (round-off).
constexpr double kRoundOff = 1e-10;
// Central differences of R (piecewise smooth: the AFT's stick/slip switches move with x) with
// h = 1e-7 of ||dx||: truncation O(h²) and cancellation O(eps/h) both ≲ 1e-7 relative away
// from a switch; we allow 1e-5.
constexpr double kDifferenceAgreement = 1e-5;

constexpr int kNodes = 6;  // per body
constexpr int kPairs = 4;  // the last kPairs nodes of each chain: nu = 12 contact rows
constexpr int kModes = 9;  // of 36: a truncated modal model, nm < nu

struct Chains {
  Eigen::MatrixXd K, M;
  std::vector<ContactPair> pairs;
  Excitation excitation;
};

// The chains of structured_solve_test.cpp; `held`: body 2's ground springs removed, so that
// only the contacts hold it (rigid-body modes held by the elements).
Chains chains(bool held = false) {
  const int n = 2 * kNodes * 3;
  Chains c;
  c.K = Eigen::MatrixXd::Zero(n, n);
  c.M = Eigen::MatrixXd::Zero(n, n);
  const double k_chain[3] = {4e4, 2e4, 3e4};
  for (int b = 0; b < 2; ++b) {
    for (int i = 0; i < kNodes; ++i) {
      for (int d = 0; d < 3; ++d) {
        const int p = 3 * (b * kNodes + i) + d;
        c.M(p, p) = 1.0 + 0.1 * i + 0.05 * b;
        if (i == 0 && !(held && b == 1)) c.K(p, p) += 10 * k_chain[d];
        if (i + 1 < kNodes) {
          const double k = k_chain[d] * (1.0 + 0.2 * ((i * 7 + d + b) % 5));
          c.K(p, p) += k;
          c.K(p + 3, p + 3) += k;
          c.K(p, p + 3) -= k;
          c.K(p + 3, p) -= k;
        }
      }
    }
  }
  for (int q = 0; q < kPairs; ++q) {
    const int a = kNodes - kPairs + q, b = kNodes + a;
    const FrictionContactParameters p{
        .kt = 2e5, .kn = 3e5, .mu = 0.4, .normal_preload = 5.0 + 3.0 * q};
    c.pairs.push_back(
        {.dofs_a = {3 * a, 3 * a + 1, 3 * a + 2},
         .dofs_b = {3 * b, 3 * b + 1, 3 * b + 2},
         .frame = Eigen::AngleAxisd(0.1 * q, Eigen::Vector3d(0, 0, 1)).toRotationMatrix(),
         .element = std::make_shared<FrictionContact3D>(p)});
  }
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  f[3 * (kNodes - 1)] = 3.0;
  f[3 * (kNodes - 1) + 1] = std::complex<double>(0, 1.0);
  f[3 * (2 * kNodes - 1)] = -2.0;
  c.excitation.harmonics[1] = f;
  return c;
}

// The lowest kModes modes; `dense_damping`: a non-proportional modal damping matrix (C = 2 M +
// 1e-5 K on body 1 only), else Rayleigh (α = 2, β = 1e-5).
LinearModel truncated(const Chains& c, bool dense_damping) {
  LinearModel full;
  if (dense_damping) {
    Eigen::MatrixXd C = 2.0 * c.M;
    const int half = static_cast<int>(c.K.rows()) / 2;
    C.topLeftCorner(half, half) += 1e-5 * c.K.topLeftCorner(half, half);
    full = linear_model_from_matrices(c.K, c.M, C);
  } else {
    full = linear_model_from_matrices(c.K, c.M, 2.0, 1e-5);
  }
  LinearModel m;
  m.omega2 = full.omega2.head(kModes);
  m.Phi = full.Phi.leftCols(kModes);
  m.modal_damping = full.modal_damping.head(kModes);
  if (dense_damping)
    m.modal_damping_matrix = full.modal_damping_matrix.topLeftCorner(kModes, kModes);
  return m;
}

HarmonicBalanceSystem make(StaticCoupling coupling, HbmLinearSolver solver, bool dense_damping) {
  const Chains c = chains();
  HarmonicBalanceOptions o;
  o.harmonics = 2;
  o.time_samples = 32;
  o.static_coupling = coupling;
  o.static_newton.tolerance = 1e-12;
  o.linear_solver = solver;
  return HarmonicBalanceSystem(truncated(c, dense_damping), c.pairs, c.excitation, o);
}

TEST(LowRankSolve, MatchesTheDensePathOnATruncatedModel) {
  for (bool dense_damping : {false, true}) {
    for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
      SCOPED_TRACE(std::string(dense_damping ? "damping matrix" : "Rayleigh") +
                   (coupling == StaticCoupling::kCoupled ? ", coupled" : ", uncoupled"));
      const HarmonicBalanceSystem dense = make(coupling, HbmLinearSolver::kDense, dense_damping);
      const HarmonicBalanceSystem low = make(coupling, HbmLinearSolver::kLowRank, dense_damping);
      const HarmonicBalanceSystem structured =
          make(coupling, HbmLinearSolver::kStructured, dense_damping);
      ASSERT_TRUE(low.low_rank());
      ASSERT_TRUE(low.has_structured_jacobian());
      ASSERT_FALSE(structured.low_rank());
      ASSERT_LT(low.linear_model().omega2.size(), low.contact_rows());
      ASSERT_TRUE(dense.static_summary().converged());
      ASSERT_TRUE(low.static_summary().converged()) << low.static_summary().message;
      // The static state: solved by Woodbury steps against the dense Newton.
      EXPECT_LE((low.static_displacement() - dense.static_displacement()).norm(),
                kStepAgreement * dense.static_displacement().norm());
      EXPECT_NEAR(low.residual_scale(), dense.residual_scale(), kRoundOff * dense.residual_scale());

      bool any_slip = false;
      for (double omega : {60.0, 95.0, 130.0}) {
        SCOPED_TRACE("omega " + std::to_string(omega));
        const Eigen::VectorXd g_dense = dense.linear_guess(omega, true);
        const Eigen::VectorXd g_low = low.linear_guess(omega, true);
        EXPECT_LE((g_low - g_dense).norm(), kStepAgreement * g_dense.norm());

        // A slipping state around the guess: the residual, and a step against the dense LU.
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(0.5, 1.5);
        Eigen::VectorXd x = g_dense;
        for (Eigen::Index i = 0; i < x.size(); ++i) x[i] *= u(rng);
        Eigen::VectorXd R, R_low;
        Eigen::MatrixXd J;
        dense.evaluate(x, omega, R, &J, nullptr);
        low.evaluate(x, omega, R_low, nullptr, nullptr);
        EXPECT_LE((R_low - R).norm(), kRoundOff * (R.norm() + x.norm()));
        const Eigen::VectorXd step_lu = J.partialPivLu().solve(-R);
        Eigen::VectorXd step;
        ASSERT_TRUE(low.solve_jacobian(x, omega, -R, step));
        EXPECT_LE((step - step_lu).norm(), kStepAgreement * step_lu.norm());
        // The same Krylov iterations as the structured solve with G_k formed: the same
        // preconditioner (exact identity), applied otherwise.
        Eigen::VectorXd step_structured;
        ASSERT_TRUE(structured.solve_jacobian(x, omega, -R, step_structured));
        EXPECT_NEAR(low.last_gmres_iterations(), structured.last_gmres_iterations(), 1);

        // The step against central differences of the low-rank residual: (R(x + h s) −
        // R(x − h s)) / 2h = dR/dx s = −R.
        const double h = 1e-7;
        Eigen::VectorXd Rp, Rm;
        low.evaluate(x + h * step, omega, Rp, nullptr, nullptr);
        low.evaluate(x - h * step, omega, Rm, nullptr, nullptr);
        EXPECT_LE(((Rp - Rm) / (2 * h) + R_low).norm(), kDifferenceAgreement * R_low.norm());

        // Newton from the guess: the same iterates.
        NewtonOptions o;
        o.tolerance = 1e-10;
        o.max_iterations = 60;
        o.reuse_jacobian = false;
        Eigen::VectorXd xd = g_dense, xl = g_dense;
        const NewtonSummary sd = solve_newton(dense, omega, xd, o);
        const NewtonSummary sl = solve_newton(low, omega, xl, o);
        ASSERT_TRUE(sd.converged()) << sd.message;
        ASSERT_TRUE(sl.converged()) << sl.message;
        EXPECT_EQ(sd.iterations, sl.iterations);
        EXPECT_LE((xl - xd).norm(), kIterateAgreement * xd.norm());
        Eigen::VectorXd F;
        std::vector<CycleStatistics> stats;
        dense.contact_forces(xd, F, &stats);
        for (const CycleStatistics& s : stats) any_slip = any_slip || s.slip_fraction > 0;
      }
      EXPECT_TRUE(any_slip);  // the preconditioner is not exact at these solutions
    }
  }
}

TEST(LowRankSolve, SweepMatchesTheDenseSweep) {
  const HarmonicBalanceSystem dense =
      make(StaticCoupling::kUncoupled, HbmLinearSolver::kDense, false);
  const HarmonicBalanceSystem low =
      make(StaticCoupling::kUncoupled, HbmLinearSolver::kLowRank, false);
  FrequencyResponseOptions o;
  for (int i = 0; i <= 10; ++i) o.omegas.push_back(60.0 + 7.0 * i);
  o.sweep.newton.tolerance = 1e-10;
  const FrequencyResponse d = frequency_response(dense, o);
  const FrequencyResponse l = frequency_response(low, o);
  ASSERT_TRUE(d.completed) << d.message;
  ASSERT_TRUE(l.completed) << l.message;
  ASSERT_EQ(d.points.size(), l.points.size());
  for (size_t i = 0; i < d.points.size(); ++i) {
    ASSERT_TRUE(d.points[i].converged && l.points[i].converged);
    EXPECT_EQ(d.points[i].omega, l.points[i].omega);
    // Both converged to 1e-10 of the residual scale; conditioning ≲ 1e3.
    EXPECT_LE((l.points[i].unknowns - d.points[i].unknowns).norm(),
              1e-6 * d.points[i].unknowns.norm())
        << "omega " << d.points[i].omega << " iterations " << d.points[i].iterations << " "
        << l.points[i].iterations << " residuals " << d.points[i].residual_norm << " "
        << l.points[i].residual_norm << " scale " << d.points[i].residual_scale;
  }
}

TEST(LowRankSolve, RefusedWithRigidBodyModesHeldByTheElements) {
  const Chains c = chains(true);
  HarmonicBalanceOptions o;
  o.harmonics = 1;
  o.time_samples = 16;
  o.linear_solver = HbmLinearSolver::kLowRank;
  try {
    const HarmonicBalanceSystem s(linear_model_from_matrices(c.K, c.M, 2.0, 0.0), c.pairs,
                                  c.excitation, o);
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("linear_solver"), std::string::npos) << e.what();
  }
  o.linear_solver = HbmLinearSolver::kAuto;  // auto: not chosen, and the case solves
  const HarmonicBalanceSystem s(linear_model_from_matrices(c.K, c.M, 2.0, 0.0), c.pairs,
                                c.excitation, o);
  EXPECT_FALSE(s.low_rank());
}

}  // namespace
}  // namespace stickslip
