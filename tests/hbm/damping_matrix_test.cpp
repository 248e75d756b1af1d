// Non-proportional modal damping (LinearModel.modal_damping_matrix = ΦᵀCΦ, dense H_k), through
// the state-space expansion and (where both are listed) the impedance LU: the dense path with a
// diagonal matrix reproduces the diagonal path; with a general C the receptance and
// the linear contact response equal dense solves of the physical matrices; μ → 0 and μN → ∞ give
// the free and stuck linear FRFs of (K + Bᵀ Kc B − Ω² M + i Ω C); dR/dx and dR/dΩ against central
// differences; the structured Newton solve against the dense LU; bad matrices are rejected.
#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "core/errors.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"
#include "hbm_test_support.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

// Products of mass-normalised modes with O(1)-conditioned matrices: equal results up to a few
// hundred ulps of the largest entries.
constexpr double kRoundOff = 1e-10;
// Nonlinear solutions compared with linear solves: Newton stops at 1e-12 of the residual scale.
constexpr double kSolutionRoundOff = 1e-9;
// Central differences with h = 1e-7 of the variable's scale: O(h²) truncation and O(eps/h)
// round-off, both ≲ 1e-8 relative.
constexpr double kFdRelativeTolerance = 1e-6;

// Two 3D nodes on ground springs with a little structural coupling, joined by a contact (6 DOFs).
// Damping: Rayleigh αM + βK plus a dashpot between DOF 0 and DOF 4 and one from DOF 2 to ground,
// so ΦᵀCΦ is far from diagonal.
struct TwoNodes {
  Eigen::MatrixXd K, M, C;
  Eigen::Matrix3d R;  // contact frame rows t1, t2, n
  FrictionContactParameters contact{.kt = 3e4, .kn = 5e4, .mu = 0.4, .normal_preload = 20.0};
  Eigen::VectorXcd load1;
};

TwoNodes two_nodes() {
  TwoNodes s;
  s.K = Eigen::MatrixXd::Zero(6, 6);
  s.M = Eigen::MatrixXd::Zero(6, 6);
  const double k[6] = {1e4, 2e4, 1.5e4, 1.2e4, 0.8e4, 2.5e4};
  const double m[6] = {1.0, 1.0, 1.0, 1.5, 1.5, 1.5};
  for (int i = 0; i < 6; ++i) {
    s.K(i, i) = k[i];
    s.M(i, i) = m[i];
  }
  s.K(0, 3) = s.K(3, 0) = -2e3;
  s.C = 2.0 * s.M + 1e-5 * s.K;
  Eigen::VectorXd e = Eigen::VectorXd::Zero(6);
  e[0] = 1.0;
  e[4] = -1.0;
  s.C += 8.0 * e * e.transpose();
  s.C(2, 2) += 5.0;
  s.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  s.load1.resize(6);
  s.load1 << Complex(3, 1), Complex(-2, 0), Complex(1, 2), 0, Complex(0.5, 0), 0;
  return s;
}

Eigen::MatrixXd contact_map(const TwoNodes& s) {  // u = B x
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, 6);
  B.leftCols(3) = s.R;
  B.rightCols(3) = -s.R;
  return B;
}

// (K + Bᵀ Kc B − Ω² M + i Ω C)⁻¹ (physical matrices, dense complex LU).
Eigen::MatrixXcd dynamic_flexibility(const TwoNodes& s, const Eigen::Vector3d& kc, double omega) {
  const Eigen::MatrixXd B = contact_map(s);
  const Eigen::MatrixXd Kc = B.transpose() * kc.asDiagonal() * B;
  Eigen::MatrixXcd D(6, 6);
  D.real() = s.K + Kc - omega * omega * s.M;
  D.imag() = omega * s.C;
  return D.partialPivLu().inverse();
}

HarmonicBalanceOptions options(StaticCoupling coupling, int harmonics, HbmLinearSolver solver,
                               DampingMatrixMethod method = DampingMatrixMethod::kStateSpace) {
  HarmonicBalanceOptions o;
  o.damping_matrix_method = method;
  o.harmonics = harmonics;
  o.time_samples = 32;
  o.static_coupling = coupling;
  o.static_newton.tolerance = 1e-12;
  o.linear_solver = solver;
  return o;
}

std::vector<ContactPair> mixed_pairs(const TwoNodes& s, const FrictionContactParameters& p) {
  std::vector<ContactPair> pairs;
  pairs.push_back({.dofs_a = {0, 1, 2},
                   .dofs_b = {3, 4, 5},
                   .frame = s.R,
                   .element = std::make_shared<FrictionContact3D>(p)});
  pairs.push_back({.dofs_a = {4},
                   .dofs_b = {},
                   .frame = Eigen::MatrixXd::Constant(1, 1, 1.0),
                   .element = std::make_shared<Jenkins1D>(
                       JenkinsParameters{.kt = 1e4, .mu = 0.3, .normal_load = 10})});
  return pairs;
}

Excitation excitation(const TwoNodes& s) {
  Excitation e;
  e.harmonics[1] = s.load1;
  return e;
}

Eigen::VectorXd random_unknowns(int n, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = amplitude * dist(rng);
  return x;
}

TEST(DampingMatrix, GeneralModalDampingIsNotDiagonal) {
  // Guards the other tests: the chosen C must couple the modes.
  const TwoNodes s = two_nodes();
  const LinearModel model = linear_model_from_matrices(s.K, s.M, s.C);
  const Eigen::MatrixXd& Cm = model.modal_damping_matrix;
  ASSERT_EQ(Cm.rows(), 6);
  const double off = (Cm - Eigen::MatrixXd(Cm.diagonal().asDiagonal())).norm();
  EXPECT_GT(off, 0.3 * Cm.diagonal().norm());
  EXPECT_LE((model.Phi.transpose() * s.M * model.Phi - Eigen::MatrixXd::Identity(6, 6)).norm(),
            kRoundOff);
}

TEST(DampingMatrix, DiagonalMatrixReproducesTheDiagonalPath) {
  const TwoNodes s = two_nodes();
  const LinearModel diagonal = linear_model_from_matrices(s.K, s.M, 2.0, 1e-5);
  LinearModel dense = diagonal;
  dense.modal_damping_matrix = diagonal.modal_damping.asDiagonal();
  dense.modal_damping.resize(0);
  for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
    const HbmLinearSolver solver = HbmLinearSolver::kDense;
    const HarmonicBalanceSystem a(diagonal, mixed_pairs(s, s.contact), excitation(s),
                                  options(coupling, 2, solver));
    const HarmonicBalanceSystem b(dense, mixed_pairs(s, s.contact), excitation(s),
                                  options(coupling, 2, solver));
    for (double omega : {60.0, 110.0, 150.0}) {
      for (int k : {1, 2}) {
        const Eigen::MatrixXcd Ga = a.receptance(k, omega);
        EXPECT_LE((b.receptance(k, omega) - Ga).norm(), kRoundOff * Ga.norm());
        const Eigen::VectorXcd ua = a.linear_contact_response(k, omega);
        EXPECT_LE((b.linear_contact_response(k, omega) - ua).norm(), kRoundOff * ua.norm());
      }
      const Eigen::VectorXd x = random_unknowns(a.size(), 6e-4, 5);
      Eigen::VectorXd Ra, Rb, dwa, dwb;
      Eigen::MatrixXd Ja, Jb;
      a.evaluate(x, omega, Ra, &Ja, &dwa);
      b.evaluate(x, omega, Rb, &Jb, &dwb);
      EXPECT_LE((Rb - Ra).norm(), kRoundOff * Ra.norm());
      EXPECT_LE((Jb - Ja).norm(), kRoundOff * Ja.norm());
      EXPECT_LE((dwb - dwa).norm(), kRoundOff * dwa.norm());
      Eigen::MatrixXcd fc = Eigen::MatrixXcd::Zero(a.contact_rows(), 3);
      fc.col(1) << Complex(1, 2), Complex(-3, 0.5), Complex(2, 0), Complex(0.7, -1);
      const Eigen::MatrixXcd xa = a.master_response(fc, omega);
      EXPECT_LE((b.master_response(fc, omega) - xa).norm(), kRoundOff * xa.norm());
    }
  }
}

TEST(DampingMatrix, ReceptanceEqualsDenseSolveOfThePhysicalMatrices) {
  // G_k = B (K − (kΩ)² M + i kΩ C)⁻¹ Bᵀ and u_lin,k = B (...)⁻¹ F_k, across the resonances.
  const TwoNodes s = two_nodes();
  for (DampingMatrixMethod method :
       {DampingMatrixMethod::kStateSpace, DampingMatrixMethod::kImpedanceLu}) {
    const HarmonicBalanceSystem sys(
        linear_model_from_matrices(s.K, s.M, s.C), {mixed_pairs(s, s.contact)[0]}, excitation(s),
        options(StaticCoupling::kCoupled, 2, HbmLinearSolver::kDense, method));
    EXPECT_EQ(sys.state_space_damping(), method == DampingMatrixMethod::kStateSpace);
    const Eigen::MatrixXd B = contact_map(s);
    for (double omega : {30.0, 72.0, 100.0, 118.0, 160.0}) {
      for (int k : {1, 2}) {
        const Eigen::MatrixXcd Dinv = dynamic_flexibility(s, Eigen::Vector3d::Zero(), k * omega);
        const Eigen::MatrixXcd ref = B.cast<Complex>() * Dinv * B.transpose().cast<Complex>();
        EXPECT_LE((sys.receptance(k, omega) - ref).norm(), kRoundOff * ref.norm()) << omega;
      }
      const Eigen::VectorXcd ul =
          B.cast<Complex>() * dynamic_flexibility(s, Eigen::Vector3d::Zero(), omega) * s.load1;
      EXPECT_LE((sys.linear_contact_response(1, omega) - ul).norm(), kRoundOff * ul.norm());
    }
  }
}

TEST(DampingMatrix, ZeroFrictionGivesFreeAndHugeFrictionGivesStuckLinearFrf) {
  // μ = 0: tangentially free, normal spring kn; μN → ∞: stuck, springs (kt, kt, kn). Both linear
  // with the general C: the HBM master response equals the dense physical solve, for the dense
  // and the structured Newton solves.
  const TwoNodes s = two_nodes();
  const Eigen::Vector3d free_k(0, 0, s.contact.kn),
      stuck_k(s.contact.kt, s.contact.kt, s.contact.kn);
  for (HbmLinearSolver solver : {HbmLinearSolver::kDense, HbmLinearSolver::kStructured}) {
    for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
      for (bool stuck : {false, true}) {
        for (DampingMatrixMethod method :
             {DampingMatrixMethod::kStateSpace, DampingMatrixMethod::kImpedanceLu}) {
          FrictionContactParameters p = s.contact;
          p.mu = stuck ? 1e9 : 0.0;
          const HarmonicBalanceSystem sys(linear_model_from_matrices(s.K, s.M, s.C),
                                          {{.dofs_a = {0, 1, 2},
                                            .dofs_b = {3, 4, 5},
                                            .frame = s.R,
                                            .element = std::make_shared<FrictionContact3D>(p)}},
                                          excitation(s), options(coupling, 2, solver, method));
          FrequencyResponseOptions o;
          o.omegas = {50, 90, 100, 118, 140, 160, 220};
          o.sweep.newton.tolerance = 1e-12;
          o.sweep.newton.max_iterations = 50;
          const FrequencyResponse r = frequency_response(sys, o);
          ASSERT_TRUE(r.completed) << r.message;
          for (const FrequencyPoint& pt : r.points) {
            const Eigen::VectorXcd ref =
                dynamic_flexibility(s, stuck ? stuck_k : free_k, pt.omega) * s.load1;
            EXPECT_LE((pt.master.col(1) - ref).norm(), kSolutionRoundOff * ref.norm()) << pt.omega;
            EXPECT_LE(pt.master.col(2).norm(), kSolutionRoundOff * ref.norm());
          }
        }
      }
    }
  }
}

TEST(DampingMatrix, JacobiansMatchFiniteDifferences) {
  // Mixed cycle (stick, slip, lift-off) with the general C, H = 2: dR/dx and dR/dΩ (the latter
  // through dH/dΩ = −H (dZ/dΩ) H) against central differences; the cycle must slip and lift off.
  const TwoNodes s = two_nodes();
  for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
    for (DampingMatrixMethod method :
         {DampingMatrixMethod::kStateSpace, DampingMatrixMethod::kImpedanceLu}) {
      const HarmonicBalanceSystem sys(linear_model_from_matrices(s.K, s.M, s.C),
                                      mixed_pairs(s, s.contact), excitation(s),
                                      options(coupling, 2, HbmLinearSolver::kDense, method));
      ASSERT_TRUE(sys.static_summary().converged());
      const Eigen::VectorXd x = random_unknowns(sys.size(), 6e-4, 3);
      testing::expect_derivatives_match_central_differences(sys, x, 110.0, 1e-7 * 6e-4,
                                                            kFdRelativeTolerance);
      testing::expect_first_pair_slips_and_separates(sys, x);
    }
  }
}

TEST(DampingMatrix, StructuredSolveMatchesDenseLu) {
  // GMRES stops at 1e-10 relative residual; this Jacobian is well conditioned (≲ 1e2).
  constexpr double kStepAgreement = 1e-7;
  const TwoNodes s = two_nodes();
  const HarmonicBalanceSystem sys(
      linear_model_from_matrices(s.K, s.M, s.C), mixed_pairs(s, s.contact), excitation(s),
      options(StaticCoupling::kCoupled, 2, HbmLinearSolver::kStructured));
  ASSERT_TRUE(sys.has_structured_jacobian());
  const Eigen::VectorXd x = random_unknowns(sys.size(), 2e-4, 11);
  const double omega = 105.0;
  Eigen::VectorXd R;
  Eigen::MatrixXd J;
  sys.evaluate(x, omega, R, &J, nullptr);
  const Eigen::VectorXd ref = J.partialPivLu().solve(-R);
  Eigen::VectorXd dx;
  ASSERT_TRUE(sys.solve_jacobian(x, omega, -R, dx));
  EXPECT_LE((dx - ref).norm(), kStepAgreement * ref.norm());
}

TEST(DampingMatrix, RejectsBadMatrices) {
  const TwoNodes s = two_nodes();
  const LinearModel good = linear_model_from_matrices(s.K, s.M, s.C);
  EXPECT_NO_THROW(validate(good));
  LinearModel wrong_size = good;
  wrong_size.modal_damping_matrix = Eigen::MatrixXd::Identity(5, 5);
  EXPECT_THROW(validate(wrong_size), InvalidInput);
  LinearModel asymmetric = good;
  asymmetric.modal_damping_matrix(0, 1) += 1.0;
  EXPECT_THROW(validate(asymmetric), InvalidInput);
  LinearModel indefinite = good;
  indefinite.modal_damping_matrix(2, 2) = -1.0;
  EXPECT_THROW(validate(indefinite), InvalidInput);
  LinearModel non_finite = good;
  non_finite.modal_damping_matrix(3, 3) = std::nan("");
  EXPECT_THROW(validate(non_finite), InvalidInput);
  EXPECT_THROW(linear_model_from_matrices(s.K, s.M, Eigen::MatrixXd::Identity(4, 4)), InvalidInput);
}

}  // namespace
}  // namespace stickslip
