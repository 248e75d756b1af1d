// Craig–Bampton reduction against independent references computed densely in the test:
// the full body's eigenfrequencies (Rayleigh–Ritz upper bounds, converging as modes are added),
// the full static solution (exact at the boundary and, through T, everywhere), TᵀKT and TᵀMT
// formed plainly from T, the Guyan reduction from its textbook formula, fixed-interface
// frequencies of (K_ii, M_ii), Rayleigh damping Tᵀ(αM+βK)T; failures reported, not thrown.
// Bodies: a seeded random 3D spring lattice with consistent bar masses (hand-made SPD system)
// and a small hex8 cantilever assembled by fe/.
#include "reduction/craig_bampton.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <vector>

#include "core/errors.h"
#include "fe/assembly.h"
#include "io/ansys_mapping.h"
#include "linalg/modal.h"
#include "mesh/mesh.h"

namespace stickslip {
namespace {

// ---------------------------------------------------------------------------------------------
// Test bodies.

struct Body {
  SparseMatrix K, M;
  std::vector<int> constrained;  // clamped DOFs
  std::vector<int> boundary;     // master DOFs
};

// nx x ny x nz nodes, spacing h; every node joined to its 13 "forward" neighbours in the 3x3x3
// stencil by an axial spring of random stiffness (seeded) and a consistent bar mass
// (m/6)[2 1; 1 2] ⊗ I. Nodes with x index 0 are clamped; the boundary is the three translations
// of the listed nodes (grid coordinates).
Body spring_lattice(int nx, int ny, int nz, const std::vector<std::array<int, 3>>& masters,
                    unsigned seed = 42) {
  const double h = 0.01, k0 = 1e6, m0 = 0.05;
  auto node = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  const int n = 3 * nx * ny * nz;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> vary(0.5, 1.5);
  std::vector<Triplet> tk, tm;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int order = di + 3 * (dj + 3 * dk);  // forward neighbours: order > 0
              if (order <= 0) continue;
              const int i2 = i + di, j2 = j + dj, k2 = k + dk;
              if (i2 < 0 || i2 >= nx || j2 < 0 || j2 >= ny || k2 < 0 || k2 >= nz) continue;
              const Eigen::Vector3d d(di * h, dj * h, dk * h);
              const Eigen::Vector3d e = d.normalized();
              const Eigen::Matrix3d ke = k0 * vary(rng) * (h / d.norm()) * e * e.transpose();
              const double me = m0 * vary(rng);
              const int a = node(i, j, k), b = node(i2, j2, k2);
              for (int p = 0; p < 3; ++p) {
                for (int q = 0; q < 3; ++q) {
                  tk.emplace_back(3 * a + p, 3 * a + q, ke(p, q));
                  tk.emplace_back(3 * b + p, 3 * b + q, ke(p, q));
                  tk.emplace_back(3 * a + p, 3 * b + q, -ke(p, q));
                  tk.emplace_back(3 * b + p, 3 * a + q, -ke(p, q));
                }
                tm.emplace_back(3 * a + p, 3 * a + p, me / 3.0);
                tm.emplace_back(3 * b + p, 3 * b + p, me / 3.0);
                tm.emplace_back(3 * a + p, 3 * b + p, me / 6.0);
                tm.emplace_back(3 * b + p, 3 * a + p, me / 6.0);
              }
            }
  Body body;
  body.K.resize(n, n);
  body.M.resize(n, n);
  body.K.setFromTriplets(tk.begin(), tk.end());
  body.M.setFromTriplets(tm.begin(), tm.end());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int d = 0; d < 3; ++d) body.constrained.push_back(3 * node(0, j, k) + d);
  for (const auto& m : masters)
    for (int d = 0; d < 3; ++d) body.boundary.push_back(3 * node(m[0], m[1], m[2]) + d);
  return body;
}

// The lattice most tests use: 12 x 3 x 3 nodes (324 DOFs, 27 clamped), masters at two tip
// corners and one node midway (9 boundary DOFs, 288 interior).
Body default_lattice() { return spring_lattice(12, 3, 3, {{11, 0, 0}, {11, 2, 2}, {6, 1, 1}}); }

// A box lx x ly x lz of ex x ey x ez C3D8 elements; node (i, j, k) has index
// i + (ex + 1) (j + (ey + 1) k) and id index + 1.
Mesh hex8_box(int ex, int ey, int ez, double lx, double ly, double lz) {
  Mesh mesh;
  auto id = [&](int i, int j, int k) { return i + (ex + 1) * (j + (ey + 1) * k); };
  for (int k = 0; k <= ez; ++k)
    for (int j = 0; j <= ey; ++j)
      for (int i = 0; i <= ex; ++i)
        mesh.add_node(id(i, j, k) + 1, Eigen::Vector3d(lx * i / ex, ly * j / ey, lz * k / ez));
  int eid = 1;
  for (int k = 0; k < ez; ++k)
    for (int j = 0; j < ey; ++j)
      for (int i = 0; i < ex; ++i) {
        const int nodes[8] = {
            id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
            id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        mesh.add_element(eid++, ElementType::kC3D8, nodes);
      }
  return mesh;
}

// A hex8 (C3D8) cantilever 0.25 x 0.05 x 0.03 m, steel, ex x ey x ez elements, clamped at x = 0;
// masters: the nodes of the tip face x = 0.25.
Body hex8_cantilever(int ex, int ey, int ez) {
  const double lx = 0.25, ly = 0.05, lz = 0.03;
  const Mesh mesh = hex8_box(ex, ey, ez, lx, ly, lz);
  auto id = [&](int i, int j, int k) { return i + (ex + 1) * (j + (ey + 1) * k); };
  Body body;
  const IsotropicMaterial steel{2e11, 0.3, 7800.0};
  assemble_stiffness_mass(mesh, steel, AssemblyOptions{}, &body.K, &body.M);
  for (int k = 0; k <= ez; ++k)
    for (int j = 0; j <= ey; ++j)
      for (int d = 0; d < 3; ++d) {
        body.constrained.push_back(3 * id(0, j, k) + d);
        body.boundary.push_back(3 * id(ex, j, k) + d);
      }
  return body;
}

// ---------------------------------------------------------------------------------------------
// Dense references.

std::vector<int> complement(int n, const std::vector<int>& a, const std::vector<int>& b = {}) {
  std::vector<char> used(n, 0);
  for (int d : a) used[d] = 1;
  for (int d : b) used[d] = 1;
  std::vector<int> out;
  for (int d = 0; d < n; ++d)
    if (!used[d]) out.push_back(d);
  return out;
}

Eigen::MatrixXd dense_block(const SparseMatrix& A, const std::vector<int>& rows,
                            const std::vector<int>& cols) {
  const Eigen::MatrixXd D(A);
  Eigen::MatrixXd B(rows.size(), cols.size());
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < cols.size(); ++j) B(i, j) = D(rows[i], cols[j]);
  return B;
}

// Natural frequencies (Hz, ascending) of the dense pencil (K, M).
Eigen::VectorXd frequencies_hz(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M, Eigen::EigenvaluesOnly);
  return es.eigenvalues().cwiseMax(0.0).cwiseSqrt() / (2.0 * kPi);
}

// The full body clamped: frequencies of (K_ff, M_ff), f = free DOFs.
Eigen::VectorXd full_frequencies_hz(const Body& b) {
  const auto free = complement(static_cast<int>(b.K.rows()), b.constrained);
  return frequencies_hz(dense_block(b.K, free, free), dense_block(b.M, free, free));
}

double max_abs(const Eigen::MatrixXd& A) { return A.cwiseAbs().maxCoeff(); }

// Every full-body mode below a quarter of the cutoff frequency (the highest fixed-interface mode
// kept) is an upper bound (Rayleigh–Ritz) within kResolvedTolerance: the truncated modes enter a
// mode at ω with weights ~(ω/ω_k)² <= 1/16, times small participation. Returns how many modes
// were checked.
int expect_resolved_below_cutoff(const Eigen::VectorXd& full, const Eigen::VectorXd& reduced,
                                 double cutoff_hz) {
  constexpr double kResolvedTolerance = 5e-4;  // relative (0.05 %)
  constexpr double kUpperBoundSlack = 1e-10;   // relative; round-off
  int checked = 0;
  for (Eigen::Index j = 0; j < full.size() && full(j) < 0.25 * cutoff_hz; ++j, ++checked) {
    const double e = (reduced(j) - full(j)) / full(j);
    EXPECT_GE(e, -kUpperBoundSlack) << "mode " << j;
    EXPECT_LT(e, kResolvedTolerance)
        << "mode " << j << " at " << full(j) << " Hz, cutoff " << cutoff_hz << " Hz";
  }
  return checked;
}

CraigBamptonResult reduce(const Body& b, int modes, int block = 128,
                          LastOrdering ordering = LastOrdering::kAuto) {
  CraigBamptonOptions o;
  o.num_modes = modes;
  o.block_size = block;
  o.coupled_last = ordering;
  CraigBamptonResult r = craig_bampton(b.K, b.M, b.constrained, b.boundary, o);
  EXPECT_TRUE(r.summary.ok()) << r.summary.message;
  return r;
}

// Products of the reduction carry the round-off of solves with K_ii (condition number of the
// lattice ~1e4) and of sums of ~1e2 terms: 1e-10 relative to the largest entry is generous.
constexpr double kProjectionTolerance = 1e-10;

// ---------------------------------------------------------------------------------------------

// Both factor orderings of K_ii: CHOLMOD's own, and the interior DOFs coupled to the boundary
// last (constraint modes by backward half solves only, K_bi Φ_c = −ZᵀZ).
class CraigBamptonOrdering : public ::testing::TestWithParam<LastOrdering> {};
INSTANTIATE_TEST_SUITE_P(BothOrderings, CraigBamptonOrdering,
                         ::testing::Values(LastOrdering::kNever, LastOrdering::kAlways));

TEST_P(CraigBamptonOrdering, ReducedMatricesEqualTransposeProjectionsThroughT) {
  const Body b = default_lattice();
  const CraigBamptonResult r = reduce(b, 20, 4, GetParam());
  EXPECT_EQ(r.summary.coupled_last > 0, GetParam() == LastOrdering::kAlways);
  const int nr = 9 + 20;
  ASSERT_EQ(r.T.rows(), b.K.rows());
  ASSERT_EQ(r.T.cols(), nr);
  ASSERT_EQ(r.body.K.rows(), nr);
  const Eigen::MatrixXd TKT = r.T.transpose() * Eigen::MatrixXd(b.K) * r.T;
  const Eigen::MatrixXd TMT = r.T.transpose() * Eigen::MatrixXd(b.M) * r.T;
  EXPECT_LE(max_abs(r.body.K - TKT), kProjectionTolerance * max_abs(TKT));
  EXPECT_LE(max_abs(r.body.M - TMT), kProjectionTolerance * max_abs(TMT));
  // Structure: K_r block diagonal with Ω² on the modal block, M_r's modal block the identity.
  EXPECT_EQ(max_abs(r.body.K.topRightCorner(9, 20)), 0.0);
  EXPECT_EQ(Eigen::VectorXd(r.body.K.bottomRightCorner(20, 20).diagonal()), r.mode_eigenvalues);
  EXPECT_EQ(r.body.M.bottomRightCorner(20, 20), Eigen::MatrixXd::Identity(20, 20));
  EXPECT_EQ(r.body.K, r.body.K.transpose());
  EXPECT_EQ(r.body.M, r.body.M.transpose());
  // T: identity at the boundary rows, zero at the clamped rows.
  for (size_t k = 0; k < b.boundary.size(); ++k) {
    Eigen::RowVectorXd e = Eigen::RowVectorXd::Zero(nr);
    e(k) = 1.0;
    EXPECT_EQ(r.T.row(b.boundary[k]), e);
  }
  for (int d : b.constrained) EXPECT_EQ(r.T.row(d).cwiseAbs().maxCoeff(), 0.0);
}

TEST_P(CraigBamptonOrdering, StaticBoundaryLoadGivesTheFullSolutionExactly) {
  const Body b = default_lattice();
  const CraigBamptonResult r = reduce(b, 30, 128, GetParam());
  const int n = static_cast<int>(b.K.rows()), nb = static_cast<int>(b.boundary.size());
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd fr = Eigen::VectorXd::Zero(r.body.size());
  for (int k = 0; k < nb; ++k) f(b.boundary[k]) = fr(k) = 100.0 * g(rng);
  // Full model, clamped DOFs eliminated, dense Cholesky (independent of CHOLMOD).
  const auto free = complement(n, b.constrained);
  Eigen::VectorXd f_free(free.size());
  for (size_t k = 0; k < free.size(); ++k) f_free(k) = f(free[k]);
  const Eigen::VectorXd x_free = dense_block(b.K, free, free).llt().solve(f_free);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < free.size(); ++k) x(free[k]) = x_free(k);
  // Reduced model.
  const Eigen::VectorXd q = r.body.K.llt().solve(fr);
  constexpr double kStaticTolerance = 1e-10;  // round-off of two SPD solves, cond ~1e4
  for (int k = 0; k < nb; ++k) {
    EXPECT_NEAR(q(k), x(b.boundary[k]), kStaticTolerance * x.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(q.tail(30).cwiseAbs().maxCoeff(), kStaticTolerance * x.cwiseAbs().maxCoeff());
  // Expansion through T recovers every DOF of the static solution.
  EXPECT_LE((r.T * q - x).cwiseAbs().maxCoeff(), kStaticTolerance * x.cwiseAbs().maxCoeff());
}

TEST(CraigBampton, FrequenciesConvergeFromAboveAsModesAreAdded) {
  const Body b = default_lattice();
  const Eigen::VectorXd full = full_frequencies_hz(b);
  constexpr int kCompared = 8;                // the lowest modes of the clamped body
  constexpr double kUpperBoundSlack = 1e-10;  // relative; Rayleigh–Ritz bound up to round-off
  constexpr double kRoundOffFloor = 1e-11;    // errors below this no longer fall measurably
  std::vector<Eigen::VectorXd> errors;
  for (int modes : {10, 30, 60}) {
    const CraigBamptonResult r = reduce(b, modes);
    const Eigen::VectorXd red = frequencies_hz(r.body.K, r.body.M);
    Eigen::VectorXd e(kCompared);
    for (int j = 0; j < kCompared; ++j) {
      e(j) = (red(j) - full(j)) / full(j);
      EXPECT_GE(e(j), -kUpperBoundSlack) << "mode " << j << " with " << modes << " modes";
    }
    errors.push_back(e);
  }
  for (int j = 0; j < kCompared; ++j) {
    for (int s = 1; s < 3; ++s) {
      if (errors[s - 1](j) < kRoundOffFloor) continue;
      EXPECT_LT(errors[s](j), errors[s - 1](j)) << "mode " << j << ", step " << s;
    }
  }
  // Modes well below the cutoff (the highest kept fixed-interface frequency) are resolved closely.
  const CraigBamptonResult r60 = reduce(b, 60);
  expect_resolved_below_cutoff(full, frequencies_hz(r60.body.K, r60.body.M),
                               r60.body.dofs.back().frequency_hz);
}

TEST(CraigBampton, WithoutModesItIsGuyanReduction) {
  const Body b = default_lattice();
  const CraigBamptonResult r = reduce(b, 0);
  const int n = static_cast<int>(b.K.rows());
  const auto interior = complement(n, b.constrained, b.boundary);
  EXPECT_EQ(r.interior_dofs, interior);
  // Textbook Guyan: K_g = K_bb − K_bi K_ii⁻¹ K_ib; M_g = T_gᵀ M T_g with T_g = [I; −K_ii⁻¹K_ib].
  const Eigen::MatrixXd Kii = dense_block(b.K, interior, interior);
  const Eigen::MatrixXd Kib = dense_block(b.K, interior, b.boundary);
  const Eigen::MatrixXd Kbb = dense_block(b.K, b.boundary, b.boundary);
  const Eigen::MatrixXd Phi = -Kii.ldlt().solve(Kib);
  const Eigen::MatrixXd Kg = Kbb + Kib.transpose() * Phi;
  Eigen::MatrixXd Tg = Eigen::MatrixXd::Zero(n, b.boundary.size());
  for (size_t k = 0; k < b.boundary.size(); ++k) Tg(b.boundary[k], k) = 1.0;
  for (size_t i = 0; i < interior.size(); ++i) Tg.row(interior[i]) = Phi.row(i);
  const Eigen::MatrixXd Mg = Tg.transpose() * Eigen::MatrixXd(b.M) * Tg;
  ASSERT_EQ(r.body.size(), 9);
  EXPECT_EQ(r.body.num_modal(), 0);
  EXPECT_LE(max_abs(r.body.K - Kg), kProjectionTolerance * max_abs(Kg));
  EXPECT_LE(max_abs(r.body.M - Mg), kProjectionTolerance * max_abs(Mg));
  EXPECT_LE(max_abs(r.T - Tg), kProjectionTolerance);
}

TEST(CraigBampton, DofMapNamesNodesDirectionsModesAndFixedInterfaceFrequencies) {
  const Body b = default_lattice();
  const CraigBamptonResult r = reduce(b, 12);
  const int n = static_cast<int>(b.K.rows());
  const auto interior = complement(n, b.constrained, b.boundary);
  const Eigen::VectorXd fixed =
      frequencies_hz(dense_block(b.K, interior, interior), dense_block(b.M, interior, interior));
  ASSERT_EQ(r.body.size(), 21);
  for (int k = 0; k < 9; ++k) {
    const ReducedDof& d = r.body.dofs[k];
    EXPECT_EQ(d.kind, ReducedDof::Kind::kPhysical);
    EXPECT_EQ(d.full_dof, b.boundary[k]);
    EXPECT_EQ(3 * d.node_index + d.direction, b.boundary[k]);
    EXPECT_EQ(d.direction, k % 3);
  }
  constexpr double kFrequencyTolerance = 1e-8;  // relative; Lanczos converged to 1e-10
  for (int j = 0; j < 12; ++j) {
    const ReducedDof& d = r.body.dofs[9 + j];
    EXPECT_EQ(d.kind, ReducedDof::Kind::kModal);
    EXPECT_EQ(d.mode, j);
    EXPECT_NEAR(d.frequency_hz, fixed(j), kFrequencyTolerance * fixed(j));
  }
  EXPECT_EQ(r.summary.num_boundary, 9);
  EXPECT_EQ(r.summary.num_interior, static_cast<int>(interior.size()));
  EXPECT_EQ(r.summary.num_constrained, 27);
  EXPECT_GT(r.summary.factor_nonzeros, 0.0);
}

TEST(CraigBampton, BothOrderingsGiveTheSameGuyanReductionToRoundOff) {
  const Body b = default_lattice();
  const CraigBamptonResult never = reduce(b, 0, 2, LastOrdering::kNever);
  const CraigBamptonResult last = reduce(b, 0, 2, LastOrdering::kAlways);
  EXPECT_EQ(never.summary.coupled_last, 0);
  // The DOFs coupled to the 3 masters: their lattice neighbours (up to 26 nodes each).
  EXPECT_GT(last.summary.coupled_last, 9);
  EXPECT_LE(max_abs(never.body.K - last.body.K), kProjectionTolerance * max_abs(never.body.K));
  EXPECT_LE(max_abs(never.body.M - last.body.M), kProjectionTolerance * max_abs(never.body.M));
  EXPECT_LE(max_abs(never.T - last.T), kProjectionTolerance * max_abs(never.T));
}

TEST(CraigBampton, BlockSizeDoesNotChangeTheResult) {
  const Body b = default_lattice();
  const CraigBamptonResult one = reduce(b, 5, 1);
  const CraigBamptonResult big = reduce(b, 5, 1000);
  const CraigBamptonResult odd = reduce(b, 5, 4);  // 9 = 4 + 4 + 1
  EXPECT_LE(max_abs(one.body.K - big.body.K), kProjectionTolerance * max_abs(big.body.K));
  EXPECT_LE(max_abs(odd.body.M - big.body.M), kProjectionTolerance * max_abs(big.body.M));
  EXPECT_LE(max_abs(odd.T.leftCols(9) - big.T.leftCols(9)), kProjectionTolerance);
}

TEST(CraigBampton, ReusedFactorSecondFactorisationAndBlockLanczosGiveTheSameBody) {
  // Default shift 0: the eigen-solve reuses the Cholesky of K_ii. A nonzero shift factorises
  // K_ii − σM_ii separately; both are Lanczos on the same pencil and must agree.
  const Body b = default_lattice();
  CraigBamptonOptions reuse;
  reuse.num_modes = 12;
  ASSERT_EQ(reuse.modal.shift, 0.0);
  CraigBamptonOptions second = reuse;
  second.modal.shift = -1.0;
  const CraigBamptonResult a = craig_bampton(b.K, b.M, b.constrained, b.boundary, reuse);
  const CraigBamptonResult c = craig_bampton(b.K, b.M, b.constrained, b.boundary, second);
  ASSERT_TRUE(a.summary.ok()) << a.summary.message;
  ASSERT_TRUE(c.summary.ok()) << c.summary.message;
  EXPECT_EQ(a.summary.modal.factorization_seconds, 0.0);  // no second factorisation
  EXPECT_GT(c.summary.modal.factorization_seconds, 0.0);
  // Eigenvalues converge to 1e-10 (Lanczos tolerance); mode vectors, hence the mass coupling,
  // to about its square root.
  constexpr double kEigenvalueTolerance = 1e-9;
  constexpr double kCouplingTolerance = 1e-6;
  EXPECT_LE(max_abs(a.mode_eigenvalues - c.mode_eigenvalues),
            kEigenvalueTolerance * c.mode_eigenvalues.maxCoeff());
  EXPECT_LE(max_abs(a.body.K - c.body.K), kEigenvalueTolerance * max_abs(c.body.K));
  EXPECT_LE(max_abs(a.body.M - c.body.M), kCouplingTolerance * max_abs(c.body.M));

  // Block Lanczos over the reused factor (automatic only for large bodies): the same body.
  CraigBamptonOptions blocked = reuse;
  blocked.modal.block_size = 4;
  const CraigBamptonResult d = craig_bampton(b.K, b.M, b.constrained, b.boundary, blocked);
  ASSERT_TRUE(d.summary.ok()) << d.summary.message;
  EXPECT_EQ(d.summary.modal.block_size, 4);
  EXPECT_LE(max_abs(d.mode_eigenvalues - c.mode_eigenvalues),
            kEigenvalueTolerance * c.mode_eigenvalues.maxCoeff());
  EXPECT_LE(max_abs(d.body.K - c.body.K), kEigenvalueTolerance * max_abs(c.body.K));
  EXPECT_LE(max_abs(d.body.M - c.body.M), kCouplingTolerance * max_abs(c.body.M));
}

TEST(CraigBampton, RayleighDampingReducesConsistentlyAndModalRatioAddsToModes) {
  const Body b = default_lattice();
  const CraigBamptonResult r = reduce(b, 6);
  const double alpha = 5.0, beta = 2e-6, zeta = 0.01;
  const Eigen::MatrixXd C_full = alpha * Eigen::MatrixXd(b.M) + beta * Eigen::MatrixXd(b.K);
  const Eigen::MatrixXd TCT = r.T.transpose() * C_full * r.T;
  const Eigen::MatrixXd C = reduced_damping(r.body, {alpha, beta, 0.0});
  EXPECT_LE(max_abs(C - TCT), kProjectionTolerance * max_abs(TCT));
  const Eigen::MatrixXd Cz = reduced_damping(r.body, {alpha, beta, zeta});
  Eigen::MatrixXd added = Cz - C;
  for (int j = 0; j < 6; ++j) {
    const double omega = std::sqrt(r.mode_eigenvalues(j));
    EXPECT_NEAR(added(9 + j, 9 + j), 2.0 * zeta * omega, 1e-9 * 2.0 * zeta * omega);
    added(9 + j, 9 + j) = 0.0;
  }
  EXPECT_EQ(max_abs(added), 0.0);
  EXPECT_THROW(reduced_damping(r.body, {-1.0, 0.0, 0.0}), InvalidInput);
}

TEST(CraigBampton, WithoutKeepBasisTIsEmptyAndMatricesUnchanged) {
  const Body b = default_lattice();
  CraigBamptonOptions o;
  o.num_modes = 4;
  o.keep_basis = false;
  const CraigBamptonResult r = craig_bampton(b.K, b.M, b.constrained, b.boundary, o);
  ASSERT_TRUE(r.summary.ok());
  EXPECT_EQ(r.T.size(), 0);
  const CraigBamptonResult with_t = reduce(b, 4);
  EXPECT_EQ(r.body.K, with_t.body.K);
  EXPECT_EQ(r.body.M, with_t.body.M);
}

TEST(CraigBampton, HexCantileverReproducesTheFullFrequencies) {
  const Body b = hex8_cantilever(10, 2, 2);  // 99 nodes, 297 DOFs; 9 tip nodes are masters
  const Eigen::VectorXd full = full_frequencies_hz(b);
  const CraigBamptonResult r = reduce(b, 40);
  const Eigen::VectorXd red = frequencies_hz(r.body.K, r.body.M);
  EXPECT_GE(expect_resolved_below_cutoff(full, red, r.body.dofs.back().frequency_hz), 3);
  const Eigen::MatrixXd TKT = r.T.transpose() * Eigen::MatrixXd(b.K) * r.T;
  EXPECT_LE(max_abs(r.body.K - TKT), kProjectionTolerance * max_abs(TKT));
}

// The two ways a reduced body enters stickslip give the same body: reduced here, exported as
// ANSYS HBMAT files (RSA + mapping) and read back as an imported body.
TEST(CraigBampton, ReducedBodySurvivesHbmatExportAndImport) {
  const Body b = default_lattice();
  CraigBamptonResult r = reduce(b, 15);
  std::vector<int> ids(b.K.rows() / 3);
  for (size_t k = 0; k < ids.size(); ++k) ids[k] = 1000 + 2 * static_cast<int>(k);
  ReducedBody short_ids = r.body;
  EXPECT_THROW(assign_node_ids(short_ids, std::vector<int>{1, 2}), InvalidInput);
  assign_node_ids(r.body, ids);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("stickslip_cb_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_ansys_reduced_body((dir / "K2.txt").string(), (dir / "M2.txt").string(), r.body);
  const ReducedBody in =
      read_ansys_reduced_body((dir / "K2.txt").string(), (dir / "M2.txt").string());
  std::filesystem::remove_all(dir);
  EXPECT_EQ(in.K, r.body.K);  // 17 significant digits: exact
  EXPECT_EQ(in.M, r.body.M);
  ASSERT_EQ(in.size(), r.body.size());
  constexpr double kFrequencyTolerance = 1e-9;  // sqrt(K_jj/M_jj) vs the Lanczos ω: round-off
  for (int k = 0; k < in.size(); ++k) {
    const ReducedDof &a = in.dofs[k], &e = r.body.dofs[k];
    EXPECT_EQ(a.kind, e.kind);
    if (e.kind == ReducedDof::Kind::kPhysical) {
      EXPECT_EQ(a.node_id, 1000 + 2 * e.node_index);
      EXPECT_EQ(a.direction, e.direction);
    } else {
      EXPECT_EQ(a.mode, e.mode);
      EXPECT_NEAR(a.frequency_hz, e.frequency_hz, kFrequencyTolerance * e.frequency_hz);
    }
  }
}

TEST(CraigBampton, IndefiniteStiffnessIsReportedNotThrown) {
  Body b = default_lattice();
  b.K = -b.K;
  CraigBamptonOptions o;
  o.num_modes = 5;
  const CraigBamptonResult r = craig_bampton(b.K, b.M, b.constrained, b.boundary, o);
  EXPECT_EQ(r.summary.termination, CraigBamptonTermination::kFactorizationFailed);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_NE(r.summary.message.find("K_ii"), std::string::npos) << r.summary.message;
}

TEST(CraigBampton, FailedEigenSolveIsReportedNotThrown) {
  const Body b = default_lattice();
  CraigBamptonOptions o;
  o.num_modes = 20;
  o.modal.subspace_size = 21;  // the smallest Lanczos basis, one restart: cannot converge
  o.modal.max_iterations = 1;
  o.modal.tolerance = 1e-15;
  const CraigBamptonResult r = craig_bampton(b.K, b.M, b.constrained, b.boundary, o);
  EXPECT_EQ(r.summary.termination, CraigBamptonTermination::kEigenSolveFailed) << r.summary.message;
  EXPECT_NE(r.summary.message.find("eigen"), std::string::npos);
}

TEST(CraigBampton, BadInputThrowsInvalidInput) {
  const Body b = default_lattice();
  CraigBamptonOptions o;
  o.num_modes = 3;
  auto run = [&](std::vector<int> c, std::vector<int> m, const CraigBamptonOptions& opt) {
    return craig_bampton(b.K, b.M, c, m, opt);
  };
  EXPECT_THROW(run(b.constrained, {0, 1, 2000}, o), InvalidInput);        // out of range
  EXPECT_THROW(run(b.constrained, {60, 61, 60}, o), InvalidInput);        // repeated
  EXPECT_THROW(run(b.constrained, {b.constrained[0]}, o), InvalidInput);  // both lists
  CraigBamptonOptions too_many = o;
  too_many.num_modes = 289;  // > number of interior DOFs (288; all of them is allowed)
  EXPECT_THROW(run(b.constrained, b.boundary, too_many), InvalidInput);
  CraigBamptonOptions negative = o;
  negative.num_modes = -1;
  EXPECT_THROW(validate(negative), InvalidInput);
  CraigBamptonOptions block = o;
  block.block_size = 0;
  EXPECT_THROW(validate(block), InvalidInput);
  const SparseMatrix small(5, 5);
  EXPECT_THROW(craig_bampton(b.K, small, b.constrained, b.boundary, o), InvalidInput);
}


// ---------------------------------------------------------------------------------------------
// Issue 22: adding fixed-interface modes can only lower the reduced frequencies (Rayleigh–Ritz on
// nested subspaces), up to every interior mode, which gives the full body's frequencies. The
// bodies include free ones held by springs to the ground on their boundary DOFs (the springs
// added to the reduced stiffness, where they act) and steel bars whose high fixed-interface modes
// lie far above 26 kHz: there the Lanczos convergence test used to be absolute, the modes were
// accepted unconverged and not M-orthogonal, and the reduced frequencies rose (or the reduced mass
// was indefinite) as modes were added.

struct SpringHeldBody {
  Body body;
  double spring = 0.0;  // N/m on every boundary DOF, to the ground
};

// Lowest `count` frequencies (Hz) of the reduced body with its springs, through the library's
// Jacobi-scaled dense solve, as ω² (rad/s)².
Eigen::VectorXd spring_held_eigenvalues(const CraigBamptonResult& r, double spring) {
  Eigen::MatrixXd K = r.body.K;
  for (int k = 0; k < r.body.num_physical(); ++k) K(k, k) += spring;
  const ModalResult m = dense_modes(K, r.body.M);
  EXPECT_TRUE(m.summary.ok()) << m.summary.message;
  return m.eigenvalues;
}

// A steel hex8 bar lx x ly x lz with ex x ey x ez elements and no clamp; the boundary is the face
// x = 0 (held by springs in the test).
Body free_hex8_bar(int ex, int ey, int ez, double lx, double ly, double lz) {
  const Mesh mesh = hex8_box(ex, ey, ez, lx, ly, lz);
  auto id = [&](int i, int j, int k) { return i + (ex + 1) * (j + (ey + 1) * k); };
  Body body;
  const IsotropicMaterial steel{2.1e11, 0.3, 7850.0};
  assemble_stiffness_mass(mesh, steel, AssemblyOptions{}, &body.K, &body.M);
  for (int k = 0; k <= ez; ++k)
    for (int j = 0; j <= ey; ++j)
      for (int d = 0; d < 3; ++d) body.boundary.push_back(3 * id(0, j, k) + d);
  std::sort(body.boundary.begin(), body.boundary.end());
  return body;
}

TEST(CraigBampton, NoFrequencyRisesWhenModesAreAddedUpToEveryInteriorMode) {
  std::vector<std::pair<std::string, SpringHeldBody>> bodies;
  bodies.push_back({"clamped lattice", {default_lattice(), 0.0}});
  {
    Body free = spring_lattice(10, 3, 3, {{0, 0, 0}, {0, 2, 2}, {0, 1, 1}, {0, 2, 0}}, 7);
    free.constrained.clear();
    bodies.push_back({"lattice on springs", {free, 5e5}});
  }
  bodies.push_back({"steel bar on springs", {free_hex8_bar(12, 2, 2, 0.16, 0.02, 0.02), 2e8}});
  bodies.push_back({"short steel block on springs", {free_hex8_bar(4, 3, 3, 0.02, 0.02, 0.02), 2e9}});
  // Round-off of the dense eigen-solve: an absolute error of a few eps·λ_max on every eigenvalue
  // (λ_max of the reduced model grows with the kept modes). A rise beyond that is a real one.
  constexpr double kEigenRoundOff = 1e3 * std::numeric_limits<double>::epsilon();
  constexpr int kCompared = 10;
  for (const auto& [name, held] : bodies) {
    const Body& b = held.body;
    const int interior = static_cast<int>(b.K.rows() - b.constrained.size() - b.boundary.size());
    std::vector<int> counts = {0, 1, 6, 20, 50, 100, 200, interior / 2, interior - 1, interior};
    counts.erase(std::remove_if(counts.begin(), counts.end(), [&](int c) { return c > interior; }),
                 counts.end());
    std::sort(counts.begin(), counts.end());
    counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
    Eigen::VectorXd previous;
    double previous_max = 0.0;
    for (int modes : counts) {
      const CraigBamptonResult r = reduce(b, modes);
      if (!r.summary.ok()) continue;
      // The reduced matrices are the projections TᵀKT, TᵀMT of the basis actually used.
      const Eigen::MatrixXd TMT = r.T.transpose() * Eigen::MatrixXd(b.M) * r.T;
      EXPECT_LE(max_abs(r.body.M - TMT), kProjectionTolerance * max_abs(TMT))
          << name << ", " << modes << " modes";
      const Eigen::VectorXd lambda = spring_held_eigenvalues(r, held.spring);
      EXPECT_GT(lambda(0), 0.0) << name << ", " << modes << " modes";
      if (previous.size() > 0) {
        const int compared = static_cast<int>(std::min<Eigen::Index>(
            kCompared, std::min(lambda.size(), previous.size())));
        for (int j = 0; j < compared; ++j) {
          const double slack = kEigenRoundOff * std::max(previous_max, lambda.maxCoeff());
          EXPECT_LE(lambda(j), previous(j) + slack)
              << name << ": eigenvalue " << j << " rose when the modes went to " << modes;
        }
      }
      previous = lambda;
      previous_max = lambda.maxCoeff();
    }
    // Every interior mode kept: the reduction spans the whole body, so its frequencies are the
    // full body's (with the springs), computed here from the full sparse matrices.
    SparseMatrix K = b.K;
    std::vector<int> free = complement(static_cast<int>(b.K.rows()), b.constrained);
    std::vector<int> boundary = b.boundary;
    std::sort(boundary.begin(), boundary.end());
    Eigen::MatrixXd Kf = dense_block(K, free, free), Mf = dense_block(b.M, free, free);
    for (size_t i = 0; i < free.size(); ++i) {
      if (std::binary_search(boundary.begin(), boundary.end(), free[i])) Kf(i, i) += held.spring;
    }
    const ModalResult full = dense_modes(Kf, Mf);
    for (int j = 0; j < kCompared; ++j) {
      EXPECT_NEAR(previous(j), full.eigenvalues(j), 1e-8 * full.eigenvalues(j) +
                                                        kEigenRoundOff * previous_max)
          << name << ": mode " << j << " with every interior mode";
    }
  }
}

}  // namespace
}  // namespace stickslip

// ---------------------------------------------------------------------------------------------
// Issue 22 item 3: floating interiors. Bodies whose boundary and constraints do not hold every
// rigid motion (K_ii singular): a free–free body without masters, a body held only at the nodes of
// one edge (a free rotation about it) or at one node (three). References: the full body's dense
// eigen-solve, its rigid motions from the node coordinates, and the equation K x = f itself.

namespace stickslip {
namespace {
namespace floating {

// A free steel hex8 box (SI) and the six rigid motions of its nodes (columns: translations x, y,
// z, rotations about x, y, z through the origin).
struct FreeBox {
  Body body;
  Eigen::MatrixXd rigid;
  int ex, ey, ez;
  int node(int i, int j, int k) const { return i + (ex + 1) * (j + (ey + 1) * k); }
};

FreeBox free_box(int ex, int ey, int ez, double lx, double ly, double lz) {
  FreeBox box{Body{}, Eigen::MatrixXd(), ex, ey, ez};
  const Mesh mesh = hex8_box(ex, ey, ez, lx, ly, lz);
  const IsotropicMaterial steel{2.1e11, 0.3, 7850.0};
  assemble_stiffness_mass(mesh, steel, AssemblyOptions{}, &box.body.K, &box.body.M);
  const int n = static_cast<int>(box.body.K.rows());
  box.rigid = Eigen::MatrixXd::Zero(n, 6);
  for (int a = 0; a < n / 3; ++a) {
    const Eigen::Vector3d x = mesh.coordinates.col(a);
    for (int d = 0; d < 3; ++d) box.rigid(3 * a + d, d) = 1.0;
    const Eigen::Matrix3d skew{
        {0, -x(2), x(1)}, {x(2), 0, -x(0)}, {-x(1), x(0), 0}};  // ω×x = −[x]ω
    box.rigid.block(3 * a, 3, 3, 3) = skew;
  }
  return box;
}

// Largest relative distance of the columns of R from span(T) in the M inner product.
double distance_from_span(const Eigen::MatrixXd& T, const SparseMatrix& M,
                          const Eigen::MatrixXd& R) {
  const Eigen::MatrixXd MT = M * T;
  const Eigen::MatrixXd Q = (T.transpose() * MT).ldlt().solve(MT.transpose() * R);
  double worst = 0.0;
  for (Eigen::Index j = 0; j < R.cols(); ++j)
    worst = std::max(worst, (T * Q.col(j) - R.col(j)).norm() / R.col(j).norm());
  return worst;
}

// Dense full-body eigenvalues ω² (rad/s)², ascending.
Eigen::VectorXd full_eigenvalues(const Body& b) {
  const ModalResult full = dense_modes(Eigen::MatrixXd(b.K), Eigen::MatrixXd(b.M));
  EXPECT_TRUE(full.summary.ok());
  return full.eigenvalues;
}

}  // namespace floating

TEST(CraigBamptonFloating, FreeFreeBodyWithoutMastersKeepsSixRigidModesAndTheExactElasticOnes) {
  const floating::FreeBox box = floating::free_box(6, 3, 2, 0.06, 0.03, 0.02);
  const Eigen::VectorXd full = floating::full_eigenvalues(box.body);
  for (int modes : {0, 10, 30}) {
    const CraigBamptonResult r = reduce(box.body, modes);
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    EXPECT_EQ(r.summary.num_rigid_modes, 6) << modes << " modes";
    ASSERT_EQ(r.mode_eigenvalues.size(), 6 + modes);
    EXPECT_EQ(r.body.size(), 6 + modes);
    EXPECT_EQ(r.mode_eigenvalues.head(6).norm(), 0.0);  // rigid: exactly 0 in K_r
    // Without masters the fixed-interface modes are the free body's modes: the elastic ones equal
    // the dense solve of the full body (Lanczos tolerance, 1e-10 on 1/(λ − σ)).
    for (int j = 6; j < 6 + modes; ++j)
      EXPECT_NEAR(r.mode_eigenvalues(j), full(j), 1e-8 * full(j)) << "mode " << j;
    EXPECT_LT(floating::distance_from_span(r.T, box.body.M, box.rigid), 1e-10);
    const Eigen::MatrixXd TKT = r.T.transpose() * box.body.K * r.T;
    const Eigen::MatrixXd TMT = r.T.transpose() * box.body.M * r.T;
    // Against the round-off of TᵀKT itself (Guyan: K_r = 0, TᵀKT ~ eps ‖K‖ ‖T‖²).
    const double k_scale = max_abs(Eigen::MatrixXd(box.body.K)) * std::pow(max_abs(r.T), 2);
    EXPECT_LE(max_abs(r.body.K - TKT), kProjectionTolerance * k_scale);
    EXPECT_LE(max_abs(r.body.M - TMT), kProjectionTolerance * max_abs(TMT));
  }
}

TEST(CraigBamptonFloating, BodyHeldOnOneEdgeOrNodeSpansRigidMotionAndIsExactForStatics) {
  const floating::FreeBox box = floating::free_box(8, 3, 3, 0.08, 0.03, 0.03);
  const Eigen::VectorXd full = floating::full_eigenvalues(box.body);
  const int n = static_cast<int>(box.body.K.rows());
  struct Holding {
    std::string name;
    std::vector<int> nodes;
    int rigid;  // rigid motions that leave those nodes at rest
  };
  std::vector<Holding> holdings = {
      {"edge y = z = 0", {}, 1},
      {"one node", {box.node(4, 1, 1)}, 3},
  };
  for (int i = 0; i <= box.ex; ++i) holdings[0].nodes.push_back(box.node(i, 0, 0));
  for (const Holding& h : holdings) {
    Body b = box.body;
    for (int a : h.nodes)
      for (int d = 0; d < 3; ++d) b.boundary.push_back(3 * a + d);
    Eigen::VectorXd previous;
    for (int modes : {0, 5, 20, 60}) {
      const CraigBamptonResult r = reduce(b, modes);
      ASSERT_TRUE(r.summary.ok()) << h.name << ": " << r.summary.message;
      EXPECT_EQ(r.summary.num_rigid_modes, h.rigid) << h.name;
      EXPECT_LT(floating::distance_from_span(r.T, b.M, box.rigid), 1e-10) << h.name;
      // Modes: six rigid at 0 (round-off of the dense solve), the elastic ones Rayleigh–Ritz upper
      // bounds of the full body's, falling as modes are added.
      const ModalResult red = dense_modes(r.body.K, r.body.M);
      ASSERT_TRUE(red.summary.ok());
      for (int j = 0; j < 6; ++j)  // against the first elastic eigenvalue of the full body
        EXPECT_LT(std::abs(red.eigenvalues(j)), 1e-12 * full(6)) << h.name << " mode " << j;
      for (int j = 6; j < std::min<int>(16, red.eigenvalues.size()); ++j) {
        EXPECT_GE(red.eigenvalues(j), full(j) * (1 - 1e-9)) << h.name << " mode " << j;
        if (previous.size() > j) {
          EXPECT_LE(red.eigenvalues(j), previous(j) * (1 + 1e-9));
        }
      }
      if (modes == 60) {  // the lowest elastic modes converged (to 1e-3 of ω²)
        for (int j = 6; j < 10; ++j)
          EXPECT_NEAR(red.eigenvalues(j), full(j), 1e-3 * full(j)) << h.name << " mode " << j;
      }
      previous = red.eigenvalues;
      // Statics: a self-equilibrated load on the boundary (zero force and moment resultants),
      // solved on the reduced model (its rigid modes left free: least squares), expanded, solves
      // the full K x = f.
      if (h.nodes.size() == 1) continue;  // one node carries no self-equilibrated load
      const int nb = static_cast<int>(b.boundary.size());
      Eigen::MatrixXd Rb(nb, 6);  // the rigid motions at the boundary DOFs
      for (int k = 0; k < nb; ++k) Rb.row(k) = box.rigid.row(b.boundary[k]);
      std::mt19937 rng(5);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      Eigen::VectorXd fb(nb);
      for (int k = 0; k < nb; ++k) fb(k) = u(rng);
      fb -= Rb * Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(Rb).solve(fb);
      Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
      for (int k = 0; k < nb; ++k) f(b.boundary[k]) = fb(k);
      ASSERT_LT((box.rigid.transpose() * f).norm(), 1e-12 * f.norm()) << h.name;
      const Eigen::VectorXd fr = r.T.transpose() * f;
      const Eigen::VectorXd q =
          Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(r.body.K).solve(fr);
      const Eigen::VectorXd residual = box.body.K * (r.T * q) - f;
      EXPECT_LT(residual.norm(), 1e-8 * f.norm()) << h.name << ", " << modes << " modes";
    }
  }
}

}  // namespace
}  // namespace stickslip
