// The state-space expansion of the non-proportional modal flexibility (harmonic_balance.h,
// DampingMatrixMethod::kStateSpace): G_k, u_lin, the residual, dR/dΩ and the master response
// against dense complex solves of the physical (K − (kΩ)² M + i kΩ C) written here, for a random
// non-proportionally damped model, repeated modes of identical bodies, rigid-body modes and
// overdamped modes; the same system through the impedance LU; and the fall-back to the LU when
// a mode is critically damped (defective) or C couples rigid-body and elastic modes.
#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "hbm/damped_modes.h"
#include "hbm/harmonic_balance.h"
#include "hbm_test_support.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

// Receptances from mass-normalised modes against dense solves of O(1e3)-conditioned impedances:
// agreement to ~1e-13; near a resonance the impedance's condition number reaches ~1/ζ ≈ 1e2.
constexpr double kRoundOff = 1e-10;
// Central differences in Ω with h = 1e-6 Ω: O(h²) truncation and O(eps/h) round-off ≲ 1e-9.
constexpr double kFdTolerance = 1e-6;

struct Physical {
  Eigen::MatrixXd K, M, C;
};

Eigen::MatrixXcd impedance(const Physical& p, double w) {
  Eigen::MatrixXcd D(p.K.rows(), p.K.cols());
  D.real() = p.K - w * w * p.M;
  D.imag() = w * p.C;
  return D;
}

Eigen::MatrixXd random_matrix(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::MatrixXd A(rows, cols);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = dist(rng);
  return A;
}

// 8 DOFs: random SPD K (frequencies ≈ 70–250 rad/s), SPD M, PSD C of rank 3 (far from
// proportional) plus a little mass-proportional damping.
Physical random_model(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = 8;
  Physical p;
  const Eigen::MatrixXd G = random_matrix(n, n, rng), R = random_matrix(n, n, rng);
  p.K = 1e4 * (G.transpose() * G + 0.5 * Eigen::MatrixXd::Identity(n, n));
  p.M = Eigen::MatrixXd::Identity(n, n) + 0.1 * R.transpose() * R;
  const Eigen::MatrixXd L = random_matrix(n, 3, rng);
  p.C = 4.0 * L * L.transpose() + 0.5 * p.M;
  return p;
}

Eigen::Matrix3d frame() {
  return Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

// A 3D friction contact between DOFs {0,1,2} and {3,4,5}, and a 1D Jenkins element on DOF 6 to
// ground.
std::vector<ContactPair> pairs() {
  const FrictionContactParameters contact{.kt = 3e4, .kn = 5e4, .mu = 0.4, .normal_preload = 20};
  std::vector<ContactPair> p;
  p.push_back({.dofs_a = {0, 1, 2},
               .dofs_b = {3, 4, 5},
               .frame = frame(),
               .element = std::make_shared<FrictionContact3D>(contact)});
  p.push_back({.dofs_a = {6},
               .dofs_b = {},
               .frame = Eigen::MatrixXd::Constant(1, 1, 1.0),
               .element = std::make_shared<Jenkins1D>(
                   JenkinsParameters{.kt = 1e4, .mu = 0.3, .normal_load = 10})});
  return p;
}

Eigen::MatrixXd contact_map(const std::vector<ContactPair>& pairs, int ndof) {  // u = B x
  int rows = 0;
  for (const ContactPair& c : pairs) rows += static_cast<int>(c.frame.rows());
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(rows, ndof);
  int r = 0;
  for (const ContactPair& c : pairs) {
    const int m = static_cast<int>(c.frame.rows());
    for (size_t i = 0; i < c.dofs_a.size(); ++i) B.block(r, c.dofs_a[i], m, 1) += c.frame.col(i);
    for (size_t i = 0; i < c.dofs_b.size(); ++i) B.block(r, c.dofs_b[i], m, 1) -= c.frame.col(i);
    r += m;
  }
  return B;
}

Excitation excitation(int ndof) {
  Excitation e;
  e.harmonics[1] = Eigen::VectorXcd::Zero(ndof);
  e.harmonics[1] << Complex(3, 1), Complex(-2, 0), Complex(1, 2), 0, Complex(0.5, 0), 0,
      Complex(1, -1), Complex(0, 2);
  e.harmonics[2] = 0.3 * e.harmonics[1].reverse();
  return e;
}

HarmonicBalanceOptions options(DampingMatrixMethod method, StaticCoupling coupling) {
  HarmonicBalanceOptions o;
  o.harmonics = 2;
  o.time_samples = 32;
  o.static_coupling = coupling;
  o.static_newton.tolerance = 1e-12;
  o.linear_solver = HbmLinearSolver::kDense;
  o.damping_matrix_method = method;
  return o;
}

LinearModel modal_model(const Physical& p) { return linear_model_from_matrices(p.K, p.M, p.C); }

Eigen::VectorXd random_unknowns(int n, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = amplitude * dist(rng);
  return x;
}

// G_k = B D⁻¹ Bᵀ, u_lin,k = B D⁻¹ F_k (k = 1, 2) and the master response x_k = D⁻¹(F_k − Bᵀ f_k)
// of `sys` against dense solves of the physical matrices, over `omegas`.
void expect_linear_operators_match(const HarmonicBalanceSystem& sys, const Physical& p,
                                   const std::vector<ContactPair>& pr, const Excitation& e,
                                   const std::vector<double>& omegas) {
  const Eigen::MatrixXcd B = contact_map(pr, static_cast<int>(p.K.rows())).cast<Complex>();
  const int nu = sys.contact_rows();
  Eigen::MatrixXcd fc = Eigen::MatrixXcd::Zero(nu, 3);
  for (int r = 0; r < nu; ++r) {
    fc(r, 1) = Complex(1.0 + r, 0.5 - r);
    fc(r, 2) = Complex(-0.3 * r, 0.7);
  }
  for (double omega : omegas) {
    const Eigen::MatrixXcd x = sys.master_response(fc, omega);
    for (int k : {1, 2}) {
      const auto lu = impedance(p, k * omega).partialPivLu();
      const Eigen::MatrixXcd G = B * lu.solve(B.transpose());
      EXPECT_LE((sys.receptance(k, omega) - G).norm(), kRoundOff * G.norm()) << omega << " " << k;
      const Eigen::VectorXcd ul = B * lu.solve(e.harmonics.at(k));
      EXPECT_LE((sys.linear_contact_response(k, omega) - ul).norm(), kRoundOff * ul.norm())
          << omega << " " << k;
      const Eigen::VectorXcd xk = lu.solve(e.harmonics.at(k) - B.transpose() * fc.col(k));
      EXPECT_LE((x.col(k) - xk).norm(), kRoundOff * xk.norm()) << omega << " " << k;
    }
  }
}

// R(x, Ω) built from dense physical solves and the element forces at x (coupled statics: all
// harmonics of x, harmonic 0 with the static flexibility K⁻¹).
Eigen::VectorXd reference_residual(const HarmonicBalanceSystem& sys, const Physical& p,
                                   const std::vector<ContactPair>& pr, const Excitation& e,
                                   const Eigen::VectorXd& x, double omega) {
  const Eigen::MatrixXcd B = contact_map(pr, static_cast<int>(p.K.rows())).cast<Complex>();
  Eigen::VectorXd F;
  sys.contact_forces(x, F, nullptr);
  const HarmonicSet& set = sys.unknown_harmonics();
  const int nu = sys.contact_rows(), nc = sys.size() / nu;
  Eigen::VectorXd R(x.size());
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    Eigen::VectorXcd U(nu), Fk(nu);
    for (int r = 0; r < nu; ++r) {
      U[r] = Complex(x[r * nc + o], k > 0 ? -x[r * nc + o + 1] : 0.0);
      Fk[r] = Complex(F[r * nc + o], k > 0 ? -F[r * nc + o + 1] : 0.0);
    }
    const auto lu = impedance(p, k * omega).partialPivLu();
    Eigen::VectorXcd Rk = U + B * lu.solve(B.transpose() * Fk);
    const auto load = e.harmonics.find(k);
    if (load != e.harmonics.end()) Rk -= B * lu.solve(load->second);
    for (int r = 0; r < nu; ++r) {
      R[r * nc + o] = Rk[r].real();
      if (k > 0) R[r * nc + o + 1] = -Rk[r].imag();
    }
  }
  return R;
}

TEST(StateSpaceDamping, RandomNonProportionalModelMatchesDenseSolves) {
  const Physical p = random_model(7);
  const LinearModel model = modal_model(p);
  const Eigen::MatrixXd& Cm = model.modal_damping_matrix;
  ASSERT_GT((Cm - Eigen::MatrixXd(Cm.diagonal().asDiagonal())).norm(), 0.3 * Cm.diagonal().norm());
  const HarmonicBalanceSystem sys(
      model, pairs(), excitation(8),
      options(DampingMatrixMethod::kStateSpace, StaticCoupling::kCoupled));
  ASSERT_TRUE(sys.state_space_damping()) << sys.damping_matrix_note();
  // Below, between and above the resonances (ω_r ≈ 70–250 rad/s), and at each of them.
  std::vector<double> omegas = {20.0, 95.0, 160.0, 400.0};
  for (int r = 0; r < model.omega2.size(); ++r) omegas.push_back(std::sqrt(model.omega2[r]));
  expect_linear_operators_match(sys, p, pairs(), excitation(8), omegas);
}

TEST(StateSpaceDamping, ResidualAndFrequencyDerivativeMatchDenseSolves) {
  // R = x − u_lin + 𝔾 F(x) through the condensed operator (the weighted grams), dR/dΩ against
  // central differences of the dense-solve residual, dR/dx against central differences.
  const Physical p = random_model(7);
  const HarmonicBalanceSystem sys(
      modal_model(p), pairs(), excitation(8),
      options(DampingMatrixMethod::kStateSpace, StaticCoupling::kCoupled));
  ASSERT_TRUE(sys.state_space_damping());
  const Eigen::VectorXd x = random_unknowns(sys.size(), 6e-4, 3);
  for (double omega : {60.0, 110.0, 180.0}) {
    Eigen::VectorXd R, dRdw;
    Eigen::MatrixXd J;
    sys.evaluate(x, omega, R, &J, &dRdw);
    const Eigen::VectorXd ref = reference_residual(sys, p, pairs(), excitation(8), x, omega);
    EXPECT_LE((R - ref).norm(), kRoundOff * ref.norm()) << omega;
    const double h = 1e-6 * omega;
    const Eigen::VectorXd fd = (reference_residual(sys, p, pairs(), excitation(8), x, omega + h) -
                                reference_residual(sys, p, pairs(), excitation(8), x, omega - h)) /
                               (2 * h);
    EXPECT_LE((dRdw - fd).norm(), kFdTolerance * fd.norm()) << omega;
    testing::expect_derivatives_match_central_differences(sys, x, omega, 1e-7 * 6e-4, kFdTolerance);
  }
}

TEST(StateSpaceDamping, AgreesWithTheImpedanceLu) {
  const Physical p = random_model(11);
  for (StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
    const HarmonicBalanceSystem a(modal_model(p), pairs(), excitation(8),
                                  options(DampingMatrixMethod::kStateSpace, coupling));
    const HarmonicBalanceSystem b(modal_model(p), pairs(), excitation(8),
                                  options(DampingMatrixMethod::kImpedanceLu, coupling));
    ASSERT_TRUE(a.state_space_damping());
    ASSERT_FALSE(b.state_space_damping());
    EXPECT_TRUE(b.damping_matrix_note().empty());
    const Eigen::VectorXd x = random_unknowns(a.size(), 6e-4, 5);
    for (double omega : {70.0, 130.0}) {
      Eigen::VectorXd Ra, Rb, dwa, dwb;
      Eigen::MatrixXd Ja, Jb;
      a.evaluate(x, omega, Ra, &Ja, &dwa);
      b.evaluate(x, omega, Rb, &Jb, &dwb);
      EXPECT_LE((Ra - Rb).norm(), kRoundOff * Rb.norm());
      EXPECT_LE((Ja - Jb).norm(), kRoundOff * Jb.norm());
      EXPECT_LE((dwa - dwb).norm(), kRoundOff * dwb.norm());
    }
  }
}

// Two identical uncoupled bodies (block-diagonal K, M, C): every damped eigenvalue is repeated,
// so the eigenvectors of a pair are an arbitrary, non-orthogonal mix that the expansion must
// re-diagonalise. Damping non-proportional inside each body, or C = 5 M (C_m = 5 I).
Physical identical_bodies(bool proportional) {
  const Physical body = random_model(21);
  Physical p;
  const int n = 4;
  p.K = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  p.M = p.K;
  p.C = p.K;
  for (int b = 0; b < 2; ++b) {
    p.K.block(b * n, b * n, n, n) = body.K.topLeftCorner(n, n);
    p.M.block(b * n, b * n, n, n) = body.M.topLeftCorner(n, n);
    p.C.block(b * n, b * n, n, n) = proportional ? Eigen::MatrixXd(5.0 * body.M.topLeftCorner(n, n))
                                                 : Eigen::MatrixXd(body.C.topLeftCorner(n, n));
  }
  return p;
}

TEST(StateSpaceDamping, RepeatedModesOfIdenticalBodies) {
  for (bool proportional : {false, true}) {
    const Physical p = identical_bodies(proportional);
    const LinearModel model = modal_model(p);
    // The guard of the test: the undamped frequencies do come in equal pairs.
    for (int r = 0; r + 1 < model.omega2.size(); r += 2) {
      EXPECT_LE(std::abs(model.omega2[r + 1] - model.omega2[r]), 1e-12 * model.omega2[r]);
    }
    const HarmonicBalanceSystem sys(
        model, pairs(), excitation(8),
        options(DampingMatrixMethod::kStateSpace, StaticCoupling::kCoupled));
    ASSERT_TRUE(sys.state_space_damping()) << sys.damping_matrix_note();
    std::vector<double> omegas = {30.0, 150.0};
    for (int r = 0; r < model.omega2.size(); r += 2) omegas.push_back(std::sqrt(model.omega2[r]));
    expect_linear_operators_match(sys, p, pairs(), excitation(8), omegas);
    const Eigen::VectorXd x = random_unknowns(sys.size(), 6e-4, 9);
    Eigen::VectorXd R;
    sys.evaluate(x, omegas[2], R, nullptr, nullptr);
    const Eigen::VectorXd ref = reference_residual(sys, p, pairs(), excitation(8), x, omegas[2]);
    EXPECT_LE((R - ref).norm(), kRoundOff * ref.norm());
  }
}

// A free-free chain of 8 unit masses (one rigid-body mode) with springs k and C = relative
// dashpots + βK (C annihilates the rigid translation, so C_m does not couple it); with a dashpot
// to ground as well the rigid mode is coupled and the LU path must be used.
Physical free_chain(bool grounded_dashpot) {
  const int n = 8;
  Physical p;
  p.K = Eigen::MatrixXd::Zero(n, n);
  p.M = Eigen::MatrixXd::Identity(n, n);
  p.C = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i + 1 < n; ++i) {
    const double k = 1e4 * (1.0 + 0.3 * i), c = (i == 2 ? 6.0 : 0.0);
    for (auto [a, b, s] :
         {std::tuple{i, i, 1.0}, {i + 1, i + 1, 1.0}, {i, i + 1, -1.0}, {i + 1, i, -1.0}}) {
      p.K(a, b) += s * k;
      p.C(a, b) += s * c;
    }
  }
  p.C += 1e-4 * p.K;
  if (grounded_dashpot) p.C(5, 5) += 3.0;
  return p;
}

TEST(StateSpaceDamping, RigidBodyModesKeepTheirOwnBlock) {
  // Excitation and contacts along the chain (1D): Jenkins elements from DOF 1 and DOF 6 to
  // ground would fix the rigid mode statically, so use relative elements between DOFs.
  std::vector<ContactPair> pr;
  for (auto [a, b] : {std::pair{1, 2}, std::pair{5, 6}}) {
    pr.push_back({.dofs_a = {a},
                  .dofs_b = {b},
                  .frame = Eigen::MatrixXd::Constant(1, 1, 1.0),
                  .element = std::make_shared<Jenkins1D>(
                      JenkinsParameters{.kt = 1e4, .mu = 0.3, .normal_load = 10})});
  }
  Excitation e;
  for (int k : {1, 2}) {
    e.harmonics[k] = Eigen::VectorXcd::Zero(8);
    e.harmonics[k][0] = Complex(2.0 / k, 1);
    e.harmonics[k][7] = Complex(-1, 0.5 * k);
  }
  for (bool grounded : {false, true}) {
    const Physical p = free_chain(grounded);
    const LinearModel model = modal_model(p);
    ASSERT_LE(model.omega2.minCoeff(), 1e-9 * model.omega2.maxCoeff());
    const HarmonicBalanceSystem sys(
        model, pr, e, options(DampingMatrixMethod::kStateSpace, StaticCoupling::kUncoupled));
    EXPECT_EQ(sys.state_space_damping(), !grounded) << sys.damping_matrix_note();
    if (grounded) {
      EXPECT_NE(sys.damping_matrix_note().find("rigid"), std::string::npos);
    }
    expect_linear_operators_match(sys, p, pr, e, {15.0, 40.0, 77.0, 160.0});
  }
}

// Modal model (M = I, Φ = I) with K = diag(ω²) and a damping matrix that makes mode 0 critically
// damped (defective: a double real eigenvalue with one eigenvector) or overdamped, coupled to
// the other modes.
Physical modal_physical(double c00) {
  const int n = 8;
  Physical p;
  p.M = Eigen::MatrixXd::Identity(n, n);
  p.K = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < n; ++r) p.K(r, r) = std::pow(60.0 + 25.0 * r, 2);
  p.C = Eigen::MatrixXd::Zero(n, n);
  p.C(0, 0) = c00;
  for (int r = 1; r < n; ++r) p.C(r, r) = 2.0 + r;
  for (int r = 2; r + 1 < n; ++r) p.C(r, r + 1) = p.C(r + 1, r) = 1.0;
  return p;
}

LinearModel as_linear_model(const Physical& p) {
  LinearModel m;
  m.omega2 = p.K.diagonal();
  m.Phi = Eigen::MatrixXd::Identity(p.K.rows(), p.K.cols());
  m.modal_damping_matrix = p.C;
  return m;
}

TEST(StateSpaceDamping, CriticallyDampedModeFallsBackToTheLu) {
  const Physical p = modal_physical(2.0 * 60.0);  // c = 2ω: ζ = 1 on mode 0 (uncoupled from 1..7)
  const HarmonicBalanceSystem sys(
      as_linear_model(p), pairs(), excitation(8),
      options(DampingMatrixMethod::kStateSpace, StaticCoupling::kCoupled));
  EXPECT_FALSE(sys.state_space_damping());
  EXPECT_NE(sys.damping_matrix_note().find("critical"), std::string::npos)
      << sys.damping_matrix_note();
  expect_linear_operators_match(sys, p, pairs(), excitation(8), {30.0, 60.0, 100.0, 150.0});
}

TEST(StateSpaceDamping, OverdampedAndHeavilyDampedModesStayOnTheStateSpacePath) {
  // ζ = 0.9 (complex pair far from the imaginary axis) and ζ = 2 (two real eigenvalues).
  for (double zeta : {0.9, 2.0}) {
    const Physical p = modal_physical(2.0 * zeta * 60.0);
    const HarmonicBalanceSystem sys(
        as_linear_model(p), pairs(), excitation(8),
        options(DampingMatrixMethod::kStateSpace, StaticCoupling::kCoupled));
    ASSERT_TRUE(sys.state_space_damping()) << sys.damping_matrix_note();
    expect_linear_operators_match(sys, p, pairs(), excitation(8), {30.0, 60.0, 100.0, 150.0});
  }
}

TEST(StateSpaceDamping, ExpansionReproducesTheModalImpedanceDirectly) {
  // damped_modal_expansion alone, on the random model's modal matrices: X diag(w(κ)) Xᵀ is the
  // inverse of diag(ω²) − κ² I + iκ C_m.
  const LinearModel model = modal_model(random_model(13));
  std::string failure;
  const auto d = damped_modal_expansion(model.omega2, model.modal_damping_matrix,
                                        Eigen::VectorXd::Ones(model.omega2.size()), failure);
  ASSERT_NE(d, nullptr) << failure;
  EXPECT_EQ(d->X.cols(), 2 * model.omega2.size());
  for (double kappa : {10.0, 100.0, 1000.0}) {
    Eigen::MatrixXcd Z(8, 8);
    Z.real() = (model.omega2.array() - kappa * kappa).matrix().asDiagonal();
    Z.imag() = kappa * model.modal_damping_matrix;
    const Eigen::MatrixXcd H = d->X * d->weights(kappa).asDiagonal() * d->X.transpose();
    EXPECT_LE((Z * H - Eigen::MatrixXcd::Identity(8, 8)).norm(), kRoundOff);
    // dw/dΩ (k = 2, Ω = κ/2) against central differences of w.
    const double h = 1e-6 * kappa;
    const Eigen::VectorXcd fd = (d->weights(kappa + 2 * h) - d->weights(kappa - 2 * h)) / (2 * h);
    const Eigen::VectorXcd dw = d->weight_derivatives(2, kappa / 2);
    EXPECT_LE((dw - fd).norm(), kFdTolerance * dw.norm());
  }
}

}  // namespace
}  // namespace stickslip
