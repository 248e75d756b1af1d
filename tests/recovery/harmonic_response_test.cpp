// Full-model harmonic recovery against independent references: the assembled two-body linear
// model solved densely, K⁻¹F, beam theory, mode truncation limits and a Craig–Bampton expansion.
#include "recovery/harmonic_response.h"

#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "core/errors.h"
#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/stress.h"
#include "mesh/mesh_tools.h"
#include "recovery/stress_envelope.h"
#include "recovery_test_util.h"
#include "reduction/craig_bampton.h"

namespace stickslip {
namespace {

using testing::bar_mesh;
using testing::kSteel;
using testing::nodes_at;
using Complex = std::complex<double>;

// Two independent direct solves of the same linear system in double precision: agreement to
// round-off amplified by the condition number of D_k (~1e6 for these small bars).
constexpr double kSolverAgreement = 1e-8;

struct Body {
  Mesh mesh;
  SparseMatrix K, M;
  DofMap dofs;
};

Body make_body(const Mesh& mesh, double clamp_x) {
  Body b{mesh, {}, {}, {}};
  assemble_stiffness_mass(b.mesh, kSteel, {}, &b.K, &b.M);
  b.dofs = DofMap::from_nodes(b.mesh.num_nodes(), nodes_at(b.mesh, 0, clamp_x));
  return b;
}

// Free-DOF dense solve of D x = F (full-size result, clamped rows 0): the reference.
Eigen::VectorXcd dense_solve(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                             const Eigen::MatrixXd& K_damp, const std::vector<int>& free,
                             const Eigen::VectorXcd& F, double w, RayleighDamping d) {
  const int nf = static_cast<int>(free.size());
  Eigen::MatrixXcd D(nf, nf);
  Eigen::VectorXcd f(nf);
  for (int i = 0; i < nf; ++i) {
    f(i) = F(free[i]);
    for (int j = 0; j < nf; ++j) {
      const int a = free[i], b = free[j];
      D(i, j) = Complex(K(a, b) - w * w * M(a, b), w * (d.alpha * M(a, b) + d.beta * K_damp(a, b)));
    }
  }
  const Eigen::VectorXcd x_f = D.partialPivLu().solve(f);
  Eigen::VectorXcd x = Eigen::VectorXcd::Zero(F.size());
  for (int i = 0; i < nf; ++i) x(free[i]) = x_f(i);
  return x;
}

ModalRecoveryOptions modal_options(int num_modes, bool residual_correction = true) {
  ModalRecoveryOptions options;
  options.num_modes = num_modes;
  options.residual_correction = residual_correction;
  return options;
}

double max_relative(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Two collinear cantilevers (A clamped at x = 0, B at x = 2L) whose ends at x = L are joined by
// linear springs between coincident nodes (normal x, docs/conventions.md's contact frame). The
// reference is the assembled two-body model solved densely, with the springs in K but not in the
// damping (contact forces carry no Rayleigh damping). Recovery: each body alone, loaded by its
// excitation plus the spring forces computed from the reference solution (force on B
// +S (x_A − x_B), on A its negative), must reproduce the reference on that body.
TEST(HarmonicResponse, SpringJoinedBodiesRecoverTheAssembledLinearModel) {
  const double L = 0.3;
  const Eigen::Vector3d size(L, 0.05, 0.04);
  Body A = make_body(bar_mesh(6, 2, 2, size, ElementType::kC3D8I), 0.0);
  Body B = make_body(bar_mesh(6, 2, 2, size, ElementType::kC3D8I, Eigen::Vector3d(L, 0, 0), 1000),
                     2 * L);
  const int na = A.mesh.num_dofs(), nb = B.mesh.num_dofs(), n = na + nb;
  const RayleighDamping damping{.alpha = 5.0, .beta = 2e-6};

  // Springs between coincident nodes; frame rows t1 = y, t2 = z, n = x.
  const auto pairs =
      match_coincident_nodes(A.mesh, nodes_at(A.mesh, 0, L), B.mesh, nodes_at(B.mesh, 0, L), 1e-9);
  ASSERT_EQ(pairs.size(), 9u);
  Eigen::Matrix3d R;
  R << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  const Eigen::Matrix3d S = R.transpose() * Eigen::Vector3d(2e8, 3e8, 5e8).asDiagonal() * R;

  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), M = Eigen::MatrixXd::Zero(n, n);
  K.topLeftCorner(na, na) = Eigen::MatrixXd(A.K);
  K.bottomRightCorner(nb, nb) = Eigen::MatrixXd(B.K);
  M.topLeftCorner(na, na) = Eigen::MatrixXd(A.M);
  M.bottomRightCorner(nb, nb) = Eigen::MatrixXd(B.M);
  const Eigen::MatrixXd K_bodies = K;
  for (const auto& [a, b] : pairs) {
    const int ia = 3 * a, ib = na + 3 * b;
    K.block<3, 3>(ia, ia) += S;
    K.block<3, 3>(ib, ib) += S;
    K.block<3, 3>(ia, ib) -= S;
    K.block<3, 3>(ib, ia) -= S;
  }
  std::vector<int> free;
  for (int d = 0; d < na; ++d) {
    if (!A.dofs.is_constrained(d)) free.push_back(d);
  }
  for (int d = 0; d < nb; ++d) {
    if (!B.dofs.is_constrained(d)) free.push_back(na + d);
  }

  // Excitation per harmonic: A at its top far corner of mid-span, B at its mid-span.
  const std::vector<int> harmonics{0, 1, 3};
  const double omega = hz_to_rad_s(700.0);
  const int node_a = nodes_at(A.mesh, 0, L / 2)[0];
  const int node_b = nodes_at(B.mesh, 0, 1.5 * L).back();
  std::vector<Eigen::Vector3cd> exc_a{{Complex(10), Complex(-40), Complex(100)},
                                      {Complex(5, -3), Complex(60, 20), Complex(-50, 80)},
                                      {Complex(0, 7), Complex(-9, 4), Complex(30, -10)}};
  std::vector<Eigen::Vector3cd> exc_b{{Complex(0), Complex(25), Complex(-70)},
                                      {Complex(-8, 2), Complex(0, -35), Complex(45, 15)},
                                      {Complex(3, 3), Complex(12, 0), Complex(-6, 20)}};

  const DirectRecovery direct_a(A.K, A.M, A.dofs, damping), direct_b(B.K, B.M, B.dofs, damping);
  ASSERT_TRUE(direct_a.ok()) << direct_a.message();
  ASSERT_TRUE(direct_b.ok()) << direct_b.message();
  Eigen::MatrixXcd loads_a(na, 3), loads_b(nb, 3), ref_a(na, 3), ref_b(nb, 3);
  for (size_t h = 0; h < harmonics.size(); ++h) {
    Eigen::VectorXcd F = Eigen::VectorXcd::Zero(n);
    F.segment<3>(3 * node_a) = exc_a[h];
    F.segment<3>(na + 3 * node_b) = exc_b[h];
    const Eigen::VectorXcd x = dense_solve(K, M, K_bodies, free, F, harmonics[h] * omega, damping);
    ref_a.col(h) = x.head(na);
    ref_b.col(h) = x.tail(nb);
    Eigen::VectorXcd Fa = F.head(na), Fb = F.tail(nb);
    for (const auto& [a, b] : pairs) {
      const Eigen::Vector3cd force_on_b =
          S.cast<Complex>() * (x.segment<3>(3 * a) - x.segment<3>(na + 3 * b));
      Fb.segment<3>(3 * b) += force_on_b;
      Fa.segment<3>(3 * a) -= force_on_b;
    }
    loads_a.col(h) = Fa;
    loads_b.col(h) = Fb;
  }
  const Eigen::MatrixXcd xa = harmonic_response(direct_a, loads_a, harmonics, omega);
  const Eigen::MatrixXcd xb = harmonic_response(direct_b, loads_b, harmonics, omega);
  for (size_t h = 0; h < harmonics.size(); ++h) {
    EXPECT_LT(max_relative(xa.col(h), ref_a.col(h)), kSolverAgreement) << "harmonic " << h;
    EXPECT_LT(max_relative(xb.col(h), ref_b.col(h)), kSolverAgreement) << "harmonic " << h;
  }
  // The springs did work: the contact forces change the response substantially.
  Eigen::VectorXcd excitation_only = Eigen::VectorXcd::Zero(na);
  excitation_only.segment<3>(3 * node_a) = exc_a[1];
  const Eigen::VectorXcd free_a = direct_a.solve(excitation_only, 1, omega);
  EXPECT_GT(max_relative(free_a, ref_a.col(1)), 0.1);

  // The modal solver with residual correction and all but a few modes is close as well.
  const ModalRecoveryOptions modal = modal_options(A.dofs.num_free() - 3);
  const ModalRecovery modal_a(A.K, A.M, A.dofs, damping, modal);
  ASSERT_TRUE(modal_a.ok()) << modal_a.message();
  const Eigen::MatrixXcd xm = harmonic_response(modal_a, loads_a, harmonics, omega);
  for (size_t h = 0; h < harmonics.size(); ++h) {
    // The three missing modes are far above 3 Ω and the residual term covers them statically.
    EXPECT_LT(max_relative(xm.col(h), ref_a.col(h)), 1e-4) << "harmonic " << h;
    // harmonic_response batches all harmonics in one pass: the same as one solve per harmonic.
    const Eigen::VectorXcd single = modal_a.solve(loads_a.col(h), harmonics[h], omega);
    EXPECT_LT(max_relative(xm.col(h), single), 1e-13) << "harmonic " << h;
  }
}

// Harmonic 0 (and any harmonic at Ω = 0) is the static solution K_ff x_f = F_f, for the direct
// solver and for the modal solver with the residual correction, whatever the number of modes.
TEST(HarmonicResponse, StaticHarmonicIsExact) {
  const Mesh mesh = bar_mesh(10, 2, 2, {0.5, 0.05, 0.05}, ElementType::kC3D8);
  Body b = make_body(mesh, 0.0);
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(mesh.num_dofs());
  for (int node : nodes_at(mesh, 0, 0.5)) F.segment<3>(3 * node) << 30.0, -20.0, 100.0;
  const RayleighDamping damping{.alpha = 5.0, .beta = 1e-6};
  const DirectRecovery direct(b.K, b.M, b.dofs, damping);
  const ModalRecovery modal(b.K, b.M, b.dofs, damping, modal_options(4));
  ASSERT_TRUE(direct.ok());
  ASSERT_TRUE(modal.ok()) << modal.message();
  const SparseMatrix K_ff = b.dofs.restrict(b.K);
  const Eigen::VectorXd F_f = b.dofs.restrict(Eigen::VectorXcd(F)).real();
  // Residual of a sparse Cholesky solve: round-off times the condition number (~1e6).
  constexpr double kStaticResidual = 1e-9;
  for (const HarmonicSolver* solver :
       {static_cast<const HarmonicSolver*>(&direct), static_cast<const HarmonicSolver*>(&modal)}) {
    for (const auto& [k, omega] : {std::pair{0, 1000.0}, std::pair{2, 0.0}}) {
      const Eigen::VectorXcd x = solver->solve(F, k, omega);
      const Eigen::VectorXcd x_f = b.dofs.restrict(x);
      EXPECT_LT(x_f.imag().norm(), 1e-14 * x_f.norm());
      EXPECT_LT((K_ff * x_f.real() - F_f).norm() / F_f.norm(), kStaticResidual);
      for (int d = 0; d < mesh.num_dofs(); ++d) {
        if (b.dofs.is_constrained(d)) {
          EXPECT_EQ(x(d), Complex(0.0));
        }
      }
    }
  }
}

// Mode superposition converges to the direct solution as modes are added; the static residual
// correction makes it far more accurate for loads at a few nodes (contact forces).
TEST(HarmonicResponse, ModalConvergesToDirectAndResidualCorrectionHelps) {
  const Mesh mesh = bar_mesh(16, 2, 2, {0.4, 0.04, 0.03}, ElementType::kC3D8I);
  Body b = make_body(mesh, 0.0);
  const RayleighDamping damping{.alpha = 5.0, .beta = 0.0};
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(mesh.num_dofs());
  const std::vector<int> tip = nodes_at(mesh, 0, 0.4);
  F.segment<3>(3 * tip[0]) << Complex(20, 5), Complex(-10, 30), Complex(50, -15);
  F.segment<3>(3 * tip.back()) << Complex(-5, 0), Complex(40, 10), Complex(0, 25);
  const DirectRecovery direct(b.K, b.M, b.dofs, damping);
  const ModalRecovery probe(b.K, b.M, b.dofs, damping, modal_options(4));
  ASSERT_TRUE(probe.ok()) << probe.message();
  // Between the 3rd and 4th modes.
  const double omega =
      0.5 * (std::sqrt(probe.eigenvalues()(2)) + std::sqrt(probe.eigenvalues()(3)));
  const Eigen::VectorXcd reference = direct.solve(F, 1, omega);
  std::vector<int> all(static_cast<size_t>(mesh.num_dofs()));
  for (int d = 0; d < mesh.num_dofs(); ++d) all[static_cast<size_t>(d)] = d;

  double previous_corrected = std::numeric_limits<double>::infinity();
  for (int n : {5, 10, 20, 40, 80}) {
    const ModalRecovery plain(b.K, b.M, b.dofs, damping, modal_options(n, false));
    const ModalRecovery corrected(b.K, b.M, b.dofs, damping, modal_options(n));
    ASSERT_TRUE(plain.ok() && corrected.ok());
    const double e_plain =
        compare_responses(plain.solve(F, 1, omega), reference, all).max_relative[0];
    const double e_corrected =
        compare_responses(corrected.solve(F, 1, omega), reference, all).max_relative[0];
    RecordProperty("modes_" + std::to_string(n), std::to_string(e_plain) + " plain, " +
                                                     std::to_string(e_corrected) + " corrected");
    std::printf("modes %3d: max relative error plain %.3e, with residual correction %.3e\n", n,
                e_plain, e_corrected);
    EXPECT_LT(e_corrected, previous_corrected);
    // Precomputed attachment modes on the loaded DOFs give the same result (and a load with an
    // entry outside them falls back to the factor, still the same).
    ModalRecoveryOptions attached = modal_options(n);
    for (int node : {tip[0], tip.back()}) {
      for (int d = 0; d < 3; ++d) attached.load_dofs.push_back(3 * node + d);
    }
    const ModalRecovery with_attachment(b.K, b.M, b.dofs, damping, attached);
    const Eigen::VectorXcd x_corrected = corrected.solve(F, 1, omega);
    // Same quantities summed in a different order: round-off times the modal condition.
    constexpr double kReorderedSum = 1e-10;
    EXPECT_LT(max_relative(with_attachment.solve(F, 1, omega), x_corrected), kReorderedSum);
    attached.load_dofs.pop_back();
    const ModalRecovery partial(b.K, b.M, b.dofs, damping, attached);
    EXPECT_LT(max_relative(partial.solve(F, 1, omega), x_corrected), kReorderedSum);
    attached.residual_correction = false;
    const ModalRecovery plain_attached(b.K, b.M, b.dofs, damping, attached);
    attached.load_dofs.push_back(3 * tip.back() + 2);
    const ModalRecovery plain_all(b.K, b.M, b.dofs, damping, attached);
    const Eigen::VectorXcd x_plain = plain.solve(F, 1, omega);
    EXPECT_LT(max_relative(plain_attached.solve(F, 1, omega), x_plain), kReorderedSum);
    EXPECT_LT(max_relative(plain_all.solve(F, 1, omega), x_plain), kReorderedSum);
    EXPECT_LT(e_corrected, 0.2 * e_plain);
    previous_corrected = e_corrected;
  }
  EXPECT_LT(previous_corrected, 1e-3);
}

// Cantilever with a transverse tip load: bending stress σ_xx = −M z'/I, M = P (L − x), z' from
// the mid-plane, compared at the top and bottom surface nodes away from the clamp and the loaded
// end (Saint-Venant). This σ_xx is the exact elasticity (Saint-Venant flexure) solution there;
// the tip shear is applied as the consistent nodal loads of a uniform traction.
//  - C3D8I: incompatible modes represent the quadratic displacements of bending within each
//    element, so the error is at round-off level (measured 9e-7); 1e-4 leaves room only for the
//    clamp's Poisson restraint, which decays within ~h of x = 0.
//  - C3D8 (full integration): parasitic shear (locking) makes the elements too stiff in bending;
//    the error is mesh-dependent, growing with the element length over the thickness per layer
//    (here cubes, 4 layers: measured 0.77%); bounded by 2%.
double cantilever_stress_error(AssemblyOptions::Hex8Formulation hex8) {
  const double L = 1.0, b = 0.1, h = 0.1, P = 1000.0;
  const int nx = 40, ny = 4, nz = 4;
  const Mesh mesh = bar_mesh(nx, ny, nz, {L, b, h}, ElementType::kC3D8);
  AssemblyOptions options;
  options.hex8 = hex8;
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, kSteel, options, &K, &M);
  const DofMap dofs = DofMap::from_nodes(mesh.num_nodes(), nodes_at(mesh, 0, 0.0));
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(mesh.num_dofs());
  for (int node : nodes_at(mesh, 0, L)) {
    const double y = mesh.coordinates(1, node), z = mesh.coordinates(2, node);
    const bool edge_y = std::abs(y) < 1e-9 || std::abs(y - b) < 1e-9;
    const bool edge_z = std::abs(z) < 1e-9 || std::abs(z - h) < 1e-9;
    F(3 * node + 2) = P * (edge_y ? 0.5 : 1.0) * (edge_z ? 0.5 : 1.0) / (ny * nz);
  }
  const DirectRecovery direct(K, M, dofs, {});
  const std::vector<int> h0{0};
  const Eigen::MatrixXcd x = harmonic_response(direct, F, h0, 0.0);
  const ComplexStressMatrix s = harmonic_stresses(mesh, kSteel, options, x)[0];
  const double I = b * h * h * h / 12.0;
  int checked = 0;
  double worst = 0.0;
  for (int node = 0; node < mesh.num_nodes(); ++node) {
    const double xc = mesh.coordinates(0, node), z = mesh.coordinates(2, node);
    if (xc < 0.25 * L || xc > 0.75 * L) continue;
    if (std::abs(z) > 1e-9 && std::abs(z - h) > 1e-9) continue;
    const double expected = -P * (L - xc) * (z - h / 2) / I;
    worst = std::max(worst, std::abs(s(0, node).real() - expected) / std::abs(expected));
    ++checked;
  }
  EXPECT_EQ(checked, 21 * 5 * 2);  // 21 stations x 5 nodes across x 2 faces
  return worst;
}

TEST(HarmonicResponse, CantileverBendingStressMatchesBeamTheory) {
  constexpr double kIncompatibleTolerance = 1e-4;
  constexpr double kFullIntegrationTolerance = 0.02;
  const double e_incompatible =
      cantilever_stress_error(AssemblyOptions::Hex8Formulation::kIncompatible);
  const double e_full = cantilever_stress_error(AssemblyOptions::Hex8Formulation::kFull);
  std::printf("cantilever sigma_xx vs beam theory: C3D8I %.2e, C3D8 %.2e\n", e_incompatible,
              e_full);
  EXPECT_LT(e_incompatible, kIncompatibleTolerance);
  EXPECT_LT(e_full, kFullIntegrationTolerance);
}

// x = T q through a Craig–Bampton basis, with q from the reduced dynamic equation, agrees with the
// direct full recovery at the master DOFs and everywhere; the difference falls with the number of
// fixed-interface modes (at a frequency below the first fixed-interface mode).
TEST(HarmonicResponse, CraigBamptonExpansionApproachesDirectRecovery) {
  const Mesh mesh = bar_mesh(12, 2, 2, {0.3, 0.04, 0.04}, ElementType::kC3D8I);
  Body b = make_body(mesh, 0.0);
  const RayleighDamping damping{.alpha = 5.0, .beta = 1e-7};
  std::vector<int> masters;
  for (int node : nodes_at(mesh, 0, 0.3)) {
    for (int d = 0; d < 3; ++d) masters.push_back(3 * node + d);
  }
  std::vector<int> constrained;
  for (int d = 0; d < mesh.num_dofs(); ++d) {
    if (b.dofs.is_constrained(d)) constrained.push_back(d);
  }
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(mesh.num_dofs());
  F(masters[2]) = Complex(100, -30);
  F(masters[10]) = Complex(-20, 60);
  F(masters[13]) = Complex(0, 45);
  const double omega = hz_to_rad_s(400.0);
  const DirectRecovery direct(b.K, b.M, b.dofs, damping);
  const Eigen::MatrixXcd reference = direct.solve(F, 1, omega);
  std::vector<int> all(static_cast<size_t>(mesh.num_dofs()));
  for (int d = 0; d < mesh.num_dofs(); ++d) all[static_cast<size_t>(d)] = d;

  double previous = std::numeric_limits<double>::infinity();
  for (int n : {2, 8, 32}) {
    CraigBamptonOptions options;
    options.num_modes = n;
    const CraigBamptonResult cb = craig_bampton(b.K, b.M, constrained, masters, options);
    ASSERT_TRUE(cb.summary.ok()) << cb.summary.message;
    const Eigen::MatrixXd& Kr = cb.body.K;
    const Eigen::MatrixXd& Mr = cb.body.M;
    const Eigen::MatrixXcd Dr =
        testing::dense_dynamic_matrix(Kr, Mr, omega, damping.alpha, damping.beta);
    Eigen::VectorXcd Fr(cb.T.cols());
    Fr.real() = cb.T.transpose() * F.real();
    Fr.imag() = cb.T.transpose() * F.imag();
    const Eigen::MatrixXcd q = Dr.partialPivLu().solve(Fr);
    const Eigen::MatrixXcd x = expand_reduced_response(cb.T, q);
    // The free-row form gives the same field.
    Eigen::MatrixXd T_free(b.dofs.num_free(), cb.T.cols());
    for (int f = 0; f < b.dofs.num_free(); ++f) T_free.row(f) = cb.T.row(b.dofs.full_dof(f));
    EXPECT_LT((expand_reduced_response(T_free, b.dofs, q) - x).cwiseAbs().maxCoeff(),
              1e-14 * x.cwiseAbs().maxCoeff());
    const double at_masters = compare_responses(x, reference, masters).max_relative[0];
    const double everywhere = compare_responses(x, reference, all).max_relative[0];
    std::printf("CB %2d modes: masters %.3e, all DOFs %.3e\n", n, at_masters, everywhere);
    EXPECT_LT(everywhere, previous);
    previous = everywhere;
  }
  EXPECT_LT(previous, 1e-4);
}

// The modal form x_k = Σ_c basis_c coordinates(c, k) reproduces the modal solve, and the
// precomputed stress basis reproduces the stresses of the recovered displacement (linearity),
// with and without the residual correction.
TEST(HarmonicResponse, ModalStressBasisMatchesStressesOfTheResponse) {
  const Mesh mesh = bar_mesh(10, 2, 2, {0.25, 0.04, 0.03}, ElementType::kC3D8I);
  Body b = make_body(mesh, 0.0);
  const std::vector<int> tip = nodes_at(mesh, 0, 0.25);
  std::vector<int> load_dofs;
  for (int node : {tip[1], tip[5]}) {
    for (int d = 0; d < 3; ++d) load_dofs.push_back(3 * node + d);
  }
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(mesh.num_dofs(), 3);
  loads(load_dofs[0], 0) = 40.0;
  loads(load_dofs[5], 0) = -15.0;
  loads(load_dofs[2], 1) = Complex(30, -12);
  loads(load_dofs[4], 1) = Complex(0, 8);
  loads(load_dofs[3], 2) = Complex(-5, 5);
  const std::vector<int> harmonics{0, 1, 2};
  const double omega = hz_to_rad_s(900.0);
  // Dense sums of the same terms in another order: round-off level.
  constexpr double kLinearity = 1e-10;
  for (bool residual : {true, false}) {
    ModalRecoveryOptions options = modal_options(12, residual);
    options.load_dofs = load_dofs;
    const ModalRecovery modal(b.K, b.M, b.dofs, {.alpha = 5.0, .beta = 1e-7}, options);
    ASSERT_TRUE(modal.ok());
    const Eigen::MatrixXcd x = harmonic_response(modal, loads, harmonics, omega);
    const Eigen::MatrixXcd c = modal.coordinates(loads, harmonics, omega);
    ASSERT_EQ(c.rows(), modal.num_basis_columns());
    EXPECT_EQ(modal.num_basis_columns(), residual ? 18 : 12);
    Eigen::MatrixXcd x_basis = Eigen::MatrixXcd::Zero(mesh.num_dofs(), 3);
    for (int col = 0; col < modal.num_basis_columns(); ++col) {
      x_basis += modal.basis_column(col).cast<Complex>() * c.row(col);
    }
    const std::vector<ComplexStressMatrix> reference = harmonic_stresses(mesh, kSteel, {}, x);
    const ModalStressBasis basis(modal, mesh, kSteel, {});
    const std::vector<ComplexStressMatrix> fast = basis.stresses(modal, loads, harmonics, omega);
    // The same basis through the sparse operator, and the operator on x directly.
    const NodalStressOperator G(mesh, kSteel, {});
    const ModalStressBasis basis_g(modal, G);
    const std::vector<ComplexStressMatrix> fast_g =
        basis_g.stresses(modal, loads, harmonics, omega);
    const std::vector<ComplexStressMatrix> direct_g = G.apply(x);
    for (int h = 0; h < 3; ++h) {
      EXPECT_LT(max_relative(x_basis.col(h), x.col(h)), kLinearity);
      const double scale = reference[h].cwiseAbs().maxCoeff();
      EXPECT_LT((fast[h] - reference[h]).cwiseAbs().maxCoeff(), kLinearity * scale);
      EXPECT_LT((fast_g[h] - reference[h]).cwiseAbs().maxCoeff(), kLinearity * scale);
      EXPECT_LT((direct_g[h] - reference[h]).cwiseAbs().maxCoeff(), kLinearity * scale);
    }
    // A load off the declared DOFs cannot use the modal form.
    Eigen::MatrixXcd off = loads;
    off(3 * tip[0], 1) = 1.0;
    EXPECT_THROW(modal.coordinates(off, harmonics, omega), InvalidInput);
  }
}

TEST(HarmonicResponse, CompareResponsesPerHarmonicByHand) {
  Eigen::MatrixXcd b(3, 2), a(3, 2);
  b << Complex(3, 4), Complex(1, 0),  //
      Complex(0, 0), Complex(0, 0),   //
      Complex(0, 1), Complex(0, 0);
  a << Complex(3, 4), Complex(1, 0),  //
      Complex(9, 9), Complex(0, 0),   //
      Complex(0, 2), Complex(0, 2);
  const std::vector<int> dofs{0, 2};  // row 1 is ignored
  const ResponseDifference d = compare_responses(a, b, dofs);
  // Column 0: differences 0 and 1, reference magnitudes 5 and 1.
  EXPECT_DOUBLE_EQ(d.max_relative[0], 1.0 / 5.0);
  EXPECT_DOUBLE_EQ(d.rms_relative[0], std::sqrt(1.0 / 26.0));
  // Column 1: differences 0 and 2, reference magnitudes 1 and 0.
  EXPECT_DOUBLE_EQ(d.max_relative[1], 2.0);
  EXPECT_DOUBLE_EQ(d.rms_relative[1], 2.0);
  const ResponseDifference z = compare_responses(a, b, std::vector<int>{1});
  EXPECT_TRUE(std::isinf(z.max_relative[0]));
  EXPECT_EQ(z.max_relative[1], 0.0);
  EXPECT_THROW(compare_responses(a, b, std::vector<int>{3}), InvalidInput);
}

TEST(HarmonicResponse, BadInputThrows) {
  const Mesh mesh = bar_mesh(4, 1, 1, {0.2, 0.05, 0.05}, ElementType::kC3D8);
  Body b = make_body(mesh, 0.0);
  EXPECT_THROW(DirectRecovery(b.K, b.M, b.dofs, {.alpha = -1.0, .beta = 0.0}), InvalidInput);
  const DirectRecovery direct(b.K, b.M, b.dofs, {});
  EXPECT_THROW(direct.solve(Eigen::VectorXcd::Zero(5), 1, 10.0), InvalidInput);
  EXPECT_THROW(direct.solve(Eigen::VectorXcd::Zero(mesh.num_dofs()), -1, 10.0), InvalidInput);
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(mesh.num_dofs(), 1);
  loads(10, 0) = Complex(1, 1);
  const std::vector<int> h0{0};
  EXPECT_THROW(harmonic_response(direct, loads, h0, 10.0), InvalidInput);
  EXPECT_THROW(ModalRecovery(b.K, b.M, b.dofs, {}, modal_options(0)), InvalidInput);
  // An indefinite "stiffness": neither factor works, reported (not thrown) and solve refuses.
  const SparseMatrix minus_K = -b.K;
  const DofMap none(mesh.num_dofs(), std::vector<int>{});
  const DirectRecovery indefinite(minus_K, b.M, none, {});
  EXPECT_FALSE(indefinite.ok());
  EXPECT_FALSE(indefinite.message().empty());
  EXPECT_THROW(indefinite.solve(Eigen::VectorXcd::Zero(mesh.num_dofs()), 1, 10.0), InvalidInput);
  EXPECT_THROW(
      complex_nodal_force_vector(
          2, std::vector<ComplexNodalForce>{{.node = 2, .force = Eigen::Vector3cd::Zero()}}),
      InvalidInput);
}

// Ω exactly at an undamped resonance: one node, K = diag(4, 9, 25) N/m, M = I kg, no damping,
// Ω = 2 rad/s, so D_1 = K − 4 M has an exact zero pivot while D_0 = K and D_2 = K − 16 M are
// regular. The singular harmonic is a numerical outcome: reported in the summary with NaN
// columns (nothing thrown), the other harmonics solved exactly (closed form F_i / D_ii).
TEST(HarmonicResponse, SingularDynamicStiffnessIsReportedNotThrown) {
  std::vector<Eigen::Triplet<double>> kt{{0, 0, 4.0}, {1, 1, 9.0}, {2, 2, 25.0}};
  std::vector<Eigen::Triplet<double>> mt{{0, 0, 1.0}, {1, 1, 1.0}, {2, 2, 1.0}};
  SparseMatrix K(3, 3), M(3, 3);
  K.setFromTriplets(kt.begin(), kt.end());
  M.setFromTriplets(mt.begin(), mt.end());
  const DofMap free_dofs(3, std::vector<int>{});
  const DirectRecovery direct(K, M, free_dofs, {});
  ASSERT_TRUE(direct.ok());
  Eigen::MatrixXcd loads(3, 3);
  loads.col(0) << 1.0, 2.0, 3.0;
  loads.col(1) << Complex(1, 1), Complex(0, 2), Complex(-1, 0.5);
  loads.col(2) << Complex(2, -1), Complex(1, 0), Complex(0, 3);
  const std::vector<int> harmonics{0, 1, 2};
  const double omega = 2.0;
  RecoverySummary summary;
  Eigen::MatrixXcd x;
  ASSERT_NO_THROW(x = harmonic_response(direct, loads, harmonics, omega, &summary));
  EXPECT_FALSE(summary.ok());
  EXPECT_EQ(summary.termination, RecoveryTermination::kSingular);
  EXPECT_EQ(summary.failed_harmonics, std::vector<int>{1});
  EXPECT_NE(summary.message.find("harmonic 1"), std::string::npos) << summary.message;
  EXPECT_TRUE(x.col(1).real().array().isNaN().all());
  const Eigen::Vector3d k_diag(4.0, 9.0, 25.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::abs(x(i, 0) - loads(i, 0) / k_diag(i)), 0.0, 1e-15);
    const double d2 = k_diag(i) - 16.0;  // K − (2Ω)² M
    EXPECT_NEAR(std::abs(x(i, 2) - loads(i, 2) / d2), 0.0, 1e-15);
  }
  // Without a summary the outcome is the same NaN column; off resonance everything is solved.
  const Eigen::MatrixXcd y = harmonic_response(direct, loads, harmonics, omega);
  EXPECT_TRUE(y.col(1).real().array().isNaN().all());
  harmonic_response(direct, loads, harmonics, 2.2, &summary);
  EXPECT_TRUE(summary.ok());
  EXPECT_TRUE(summary.failed_harmonics.empty());
}

TEST(HarmonicResponse, ComplexNodalForcesAddUp) {
  const std::vector<ComplexNodalForce> forces{
      {.node = 1, .force = Eigen::Vector3cd(Complex(1, 2), 0, 0)},
      {.node = 1, .force = Eigen::Vector3cd(Complex(0, -2), 0, Complex(3, 0))}};
  const Eigen::VectorXcd f = complex_nodal_force_vector(2, forces);
  EXPECT_EQ(f(3), Complex(1, 0));
  EXPECT_EQ(f(5), Complex(3, 0));
  EXPECT_EQ(f.cwiseAbs().sum(), 4.0);
}

}  // namespace
}  // namespace stickslip

namespace stickslip {
namespace {

TEST(CompareResponses, AbsoluteDifferenceIsReportedWhereTheReferenceIsZero) {
  // Column 0: reference zero (e.g. harmonic 0 without static loads), a = (0, 3e-9, -4e-9 i);
  // column 1: reference (1, 2), a = (1.5, 2).
  Eigen::MatrixXcd a(3, 2), b(3, 2);
  a << 0.0, 1.5, 3e-9, 2.0, std::complex<double>(0, -4e-9), 7.0;
  b << 0.0, 1.0, 0.0, 2.0, 0.0, 9.0;
  const std::vector<int> dofs = {0, 1, 2};
  const ResponseDifference d = compare_responses(a, b, dofs);
  EXPECT_EQ(d.max_absolute[0], 4e-9);
  EXPECT_TRUE(std::isinf(d.max_relative[0]));
  EXPECT_EQ(d.max_absolute[1], 2.0);  // |7 − 9|
  EXPECT_DOUBLE_EQ(d.max_relative[1], 2.0 / 9.0);
}

}  // namespace
}  // namespace stickslip

namespace stickslip {
namespace {

// A free steel bar (no clamp, no support: six rigid-body modes) under a self-equilibrated static
// load (opposite forces at the two ends, a couple of forces along y). Reference: the same bar on
// 3-2-1 supports at three nodes of its x = 0 end (statically determinate: a balanced load leaves
// the reactions 0 and the deformation unchanged), solved through the ordinary clamped factor. The
// free solve must equal it up to a rigid motion, which add_rigid_motion fitted at a few DOFs puts
// back exactly; without it the result is M-orthogonal to the rigid modes. An unbalanced load is
// refused (kUnbalanced, NaN), and harmonic 1 of the free bar equals a dense complex solve.
TEST(HarmonicResponse, FreeBodyStaticResponseIsExactUpToTheRigidMotionFittedAtMasters) {
  const Mesh mesh = bar_mesh(6, 2, 2, {0.3, 0.05, 0.04}, ElementType::kC3D8);
  Body b = make_body(mesh, -1.0);  // no node at x = -1: nothing clamped
  ASSERT_EQ(b.dofs.num_free(), mesh.num_dofs());
  const std::vector<int> left = nodes_at(mesh, 0, 0.0), right = nodes_at(mesh, 0, 0.3);
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(mesh.num_dofs());
  F(3 * right[0] + 0) += 700.0;  // tension along x
  F(3 * left[0] + 0) -= 700.0;
  F(3 * right[1] + 1) += 300.0;  // a couple: +y at right[1], −y at left[1] plus the moment's
  F(3 * left[1] + 1) -= 300.0;   // balance about z through opposite x forces at two left nodes
  const Eigen::Vector3d pr = mesh.coordinates.col(right[1]), pl = mesh.coordinates.col(left[1]);
  // Moment about z of the ±300 N pair: 300 (x_r − x_l); balanced by ±f along x at two left nodes
  // a distance dy apart.
  const int l2 = left[0], l3 = left[2];  // y = 0 and y = 0.05 on the z = 0 edge
  const double dy = mesh.coordinates(1, l3) - mesh.coordinates(1, l2);
  ASSERT_GT(std::abs(dy), 1e-6);
  const double f = -300.0 * (pr.x() - pl.x()) / dy;
  F(3 * l2 + 0) += f;
  F(3 * l3 + 0) -= f;
  // Check the balance by hand: resultant and moment of F about the origin vanish.
  Eigen::Vector3d resultant = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d fn = F.segment<3>(3 * n).real();
    resultant += fn;
    moment += Eigen::Vector3d(mesh.coordinates.col(n)).cross(fn);
  }
  ASSERT_LT(resultant.norm(), 1e-9);
  ASSERT_LT(moment.norm(), 1e-9);

  const DirectRecovery free_body(b.K, b.M, b.dofs, {.alpha = 5.0, .beta = 0.0});
  ASSERT_TRUE(free_body.ok()) << free_body.message();
  const Eigen::MatrixXd rigid = free_body.rigid_modes();
  ASSERT_EQ(rigid.cols(), 6);
  const Eigen::MatrixXd K = Eigen::MatrixXd(b.K), M = Eigen::MatrixXd(b.M);
  EXPECT_LT((K * rigid).norm(), 1e-6 * K.norm() * rigid.norm());
  EXPECT_LT((rigid.transpose() * M * rigid - Eigen::MatrixXd::Identity(6, 6)).norm(), 1e-9);

  // 3-2-1: node a all three; node b (from a along y) x and z; node c (off the line ab, in the
  // plane x = 0) x.
  const int a = left[0], bn = left[1], c = left[left.size() - 1];
  ASSERT_GT((Eigen::Vector3d(mesh.coordinates.col(bn) - mesh.coordinates.col(a)))
                .cross(Eigen::Vector3d(mesh.coordinates.col(c) - mesh.coordinates.col(a)))
                .norm(),
            1e-6);
  const DofMap supported(mesh.num_dofs(),
                         std::vector<int>{3 * a, 3 * a + 1, 3 * a + 2, 3 * bn, 3 * bn + 2, 3 * c});
  const DirectRecovery held(b.K, b.M, supported, {});
  ASSERT_TRUE(held.ok()) << held.message();
  EXPECT_EQ(held.rigid_modes().cols(), 0);
  const std::vector<int> h0{0};
  const Eigen::VectorXcd x_ref = harmonic_response(held, F, h0, 0.0).col(0);

  RecoverySummary summary;
  Eigen::MatrixXcd x = harmonic_response(free_body, F, h0, 0.0, &summary);
  ASSERT_TRUE(summary.ok()) << summary.message;
  // Without rigid motion: M-orthogonal to the rigid modes, and K x = F.
  EXPECT_LT((rigid.transpose() * M * x.col(0).real()).norm(),
            1e-12 * rigid.norm() * (M * x.col(0).real()).norm());
  EXPECT_LT((K * x.col(0).real() - F.real()).norm(), 1e-8 * F.norm());
  // The rigid motion fitted at the DOFs of four "master" nodes (an end and the middle).
  std::vector<int> masters;
  for (int n : {right[0], right[1], left[2], nodes_at(mesh, 0, 0.15)[0]})
    for (int d = 0; d < 3; ++d) masters.push_back(3 * n + d);
  Eigen::VectorXcd target(static_cast<Eigen::Index>(masters.size()));
  for (size_t i = 0; i < masters.size(); ++i)
    target(static_cast<Eigen::Index>(i)) = x_ref(masters[i]);
  add_rigid_motion(rigid, masters, target, x.col(0));
  EXPECT_LT(max_relative(x.col(0), x_ref), kSolverAgreement);

  // Unbalanced: the resultant of one extra force along z has nothing to hold it.
  Eigen::VectorXcd G = F;
  G(3 * right[0] + 2) += 1.0;
  const Eigen::MatrixXcd xg = harmonic_response(free_body, G, h0, 0.0, &summary);
  EXPECT_EQ(summary.termination, RecoveryTermination::kUnbalanced);
  EXPECT_NE(summary.message.find("resultant"), std::string::npos) << summary.message;
  EXPECT_TRUE(xg.col(0).real().array().isNaN().all());

  // Harmonic 1: D_1 is regular for a free body (rigid modes: −Ω² + iΩα ≠ 0). Dense reference on
  // an unbalanced load (dynamic loads need no balance).
  const double omega = 2 * M_PI * 150.0;
  const std::vector<int> h1{1};
  std::vector<int> all(static_cast<size_t>(mesh.num_dofs()));
  for (int i = 0; i < mesh.num_dofs(); ++i) all[static_cast<size_t>(i)] = i;
  const Eigen::VectorXcd x1 = harmonic_response(free_body, G, h1, omega, &summary).col(0);
  ASSERT_TRUE(summary.ok()) << summary.message;
  const Eigen::VectorXcd x1_dense =
      dense_solve(K, M, K, all, G, omega, {.alpha = 5.0, .beta = 0.0});
  EXPECT_LT(max_relative(x1, x1_dense), kSolverAgreement);

  // The modal path: six rigid modes (exactly 0) beside 12 elastic ones. Harmonic 0 with the
  // residual correction is K⁺F, the direct solve's; the unbalanced load is refused the same way;
  // harmonic 1 is the dense solve up to the truncation the static correction leaves,
  // O((Ω/ω_13)²) of the truncated part (150 Hz against the 13th free–free mode, above 10 kHz).
  const ModalRecovery modal(b.K, b.M, b.dofs, {.alpha = 5.0, .beta = 0.0}, modal_options(12));
  ASSERT_TRUE(modal.ok()) << modal.message();
  ASSERT_EQ(modal.rigid_modes().cols(), 6);
  EXPECT_EQ(modal.eigenvalues().head(6).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(modal.eigenvalues()(6), 0.0);
  const Eigen::MatrixXcd x_direct = harmonic_response(free_body, F, h0, 0.0);
  const Eigen::MatrixXcd x_modal = harmonic_response(modal, F, h0, 0.0, &summary);
  ASSERT_TRUE(summary.ok()) << summary.message;
  EXPECT_LT(max_relative(x_modal.col(0), x_direct.col(0)), kSolverAgreement);
  harmonic_response(modal, G, h0, 0.0, &summary);
  EXPECT_EQ(summary.termination, RecoveryTermination::kUnbalanced);
  const Eigen::VectorXcd x1_modal = harmonic_response(modal, G, h1, omega, &summary).col(0);
  ASSERT_TRUE(summary.ok()) << summary.message;
  const double truncation = max_relative(x1_modal, x1_dense);
  std::printf("free bar, modal recovery (6 rigid + 12 modes, residual) at 150 Hz vs dense: %.2e\n",
              truncation);
  EXPECT_LT(truncation, 1e-3);
  // Without the correction the rigid modes are found the same way, and harmonic 0 is the modal
  // part of K⁺F only (no rigid coordinate: finite, balanced loads only).
  const ModalRecovery plain(b.K, b.M, b.dofs, {.alpha = 5.0, .beta = 0.0},
                            modal_options(12, false));
  ASSERT_TRUE(plain.ok()) << plain.message();
  ASSERT_EQ(plain.rigid_modes().cols(), 6);
  const Eigen::MatrixXcd x_plain = harmonic_response(plain, F, h0, 0.0, &summary);
  ASSERT_TRUE(summary.ok()) << summary.message;
  EXPECT_TRUE(x_plain.allFinite());
}

TEST(HarmonicResponse, AddRigidMotionLeavesUnseenMotionAtZero) {
  // Two "rigid modes" of a 4-DOF toy: e0 = (1,1,0,0)/√2 seen at DOF 0, e1 = (0,0,1,1)/√2 seen by
  // neither listed DOF: its amplitude stays 0, e0's is fitted exactly.
  Eigen::MatrixXd rigid = Eigen::MatrixXd::Zero(4, 2);
  rigid(0, 0) = rigid(1, 0) = rigid(2, 1) = rigid(3, 1) = 1.0 / std::sqrt(2.0);
  Eigen::VectorXcd x = Eigen::VectorXcd::Zero(4);
  const std::vector<int> dofs{0, 1};
  Eigen::VectorXcd target(2);
  target << Complex(2.0, 1.0), Complex(2.0, 1.0);
  const Eigen::VectorXcd a = add_rigid_motion(rigid, dofs, target, x);
  EXPECT_NEAR(std::abs(a(0) - Complex(2.0, 1.0) * std::sqrt(2.0)), 0.0, 1e-14);
  EXPECT_EQ(a(1), Complex(0.0));
  EXPECT_NEAR(std::abs(x(1) - Complex(2.0, 1.0)), 0.0, 1e-14);
  EXPECT_EQ(x(3), Complex(0.0));
  EXPECT_THROW(add_rigid_motion(rigid, std::vector<int>{7, 0}, target, x), InvalidInput);
}

}  // namespace
}  // namespace stickslip
