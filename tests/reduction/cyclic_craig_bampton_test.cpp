// Craig–Bampton per nodal diameter (reduction/cyclic_craig_bampton.h) against the sector's own
// problem of that nodal diameter (fe/cyclic.h cyclic_sector_problem, solved whole here): with
// every interior mode kept the reduced model has exactly the sector's eigenvalues; with fewer its
// eigenvalues approach them from above as modes are added (Rayleigh–Ritz on nested spaces); a
// static load on the masters is reproduced exactly by the Guyan part, at the masters and, through
// T, everywhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <complex>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "../cyclic_annulus.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "fe/cyclic.h"
#include "linalg/modal.h"
#include "reduction/cyclic_craig_bampton.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;
using testing_cyclic::Annulus;
using testing_cyclic::AnnulusShape;

constexpr int kSectors = 6, kPerSector = 3;
const AnnulusShape kShape{.radial = 3, .axial = 1};
const IsotropicMaterial kSteel{.youngs_modulus = 2.1e11, .poisson_ratio = 0.3, .density = 7800};

struct Sector {
  Annulus a;
  SparseMatrix K, M;
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> clamped;  // the inner radius
  CyclicSymmetry symmetry;
};

Sector make_sector() {
  Sector s{testing_cyclic::annulus(kSectors, kPerSector, 1, kShape), {}, {}, {}, {}, {}};
  assemble_stiffness_mass(s.a.mesh, kSteel, AssemblyOptions{}, &s.K, &s.M);
  s.symmetry.sectors = kSectors;
  s.pairs = match_cyclic_boundaries(s.a.mesh, testing_cyclic::low_nodes(s.a),
                                    testing_cyclic::high_nodes(s.a), s.symmetry, 1e-9);
  for (int n : testing_cyclic::inner_nodes(s.a))
    for (int c = 0; c < 3; ++c) s.clamped.push_back(3 * n + c);
  std::sort(s.clamped.begin(), s.clamped.end());
  return s;
}

// Masters: an outer node of the low boundary (top face) and an outer node inside the sector.
std::vector<int> masters(const Sector& s, const CyclicSectorProblem& p) {
  std::vector<int> out;
  for (int node : {s.a.node(kShape.radial, 0, 1), s.a.node(kShape.radial, 1, 0)}) {
    for (int c = 0; c < 3; ++c) {
      const int i = p.independent_index(3 * node + c);
      EXPECT_GE(i, 0);
      out.push_back(i);
    }
  }
  return out;
}

// Each eigenvalue of the sector's Hermitian problem once (the real form has the doubled ones
// twice, consecutively).
Eigen::VectorXd sector_eigenvalues(const CyclicSectorProblem& p) {
  const ModalResult r = dense_modes(p.K, p.M);
  EXPECT_TRUE(r.summary.ok());
  if (!p.doubled) return r.eigenvalues;
  Eigen::VectorXd out(r.eigenvalues.size() / 2);
  for (Eigen::Index j = 0; j < out.size(); ++j) out(j) = r.eigenvalues(2 * j);
  return out;
}

Eigen::VectorXd reduced_eigenvalues(const CyclicReducedSector& r) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> eig(r.K, r.M);
  EXPECT_EQ(eig.info(), Eigen::Success);
  return eig.eigenvalues();
}

// The sector's Hermitian stiffness, dense, from its real form.
Eigen::MatrixXcd hermitian_stiffness(const CyclicSectorProblem& p) {
  const Eigen::MatrixXd K(p.K);
  if (!p.doubled) return K.cast<Complex>();
  const Eigen::Index n = K.rows() / 2;
  return K.topLeftCorner(n, n).cast<Complex>() +
         Complex(0, 1) * K.bottomLeftCorner(n, n).cast<Complex>();
}

CraigBamptonOptions with_modes(int modes) {
  CraigBamptonOptions o;
  o.num_modes = modes;
  return o;
}

TEST(CyclicCraigBampton, EveryInteriorModeKeptGivesTheSectorsEigenvaluesForEachNodalDiameter) {
  const Sector s = make_sector();
  for (int h = 0; 2 * h <= kSectors; ++h) {
    SCOPED_TRACE("nodal diameter " + std::to_string(h));
    const CyclicSectorProblem p =
        cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, h);
    const std::vector<int> b = masters(s, p);
    const int interior = static_cast<int>(p.independent.size() - b.size());
    const CyclicReducedSector r =
        cyclic_craig_bampton(p.K, p.M, p.doubled, h, b, with_modes(interior));
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    ASSERT_EQ(r.K.rows(), static_cast<Eigen::Index>(p.independent.size()));
    // Hermitian, the modes M-orthonormal (the modal block of M_r is I) with K_r's modal block Ω².
    EXPECT_LT((r.K - r.K.adjoint()).norm(), 1e-12 * r.K.norm());
    const Eigen::Index nb = r.num_boundary();
    EXPECT_LT(
        (r.M.bottomRightCorner(interior, interior) - Eigen::MatrixXcd::Identity(interior, interior))
            .norm(),
        1e-9 * interior);
    const Eigen::VectorXd exact = sector_eigenvalues(p), reduced = reduced_eigenvalues(r);
    ASSERT_EQ(reduced.size(), exact.size());
    for (Eigen::Index j = 0; j < exact.size(); ++j)
      EXPECT_NEAR(reduced(j), exact(j), 1e-9 * exact(j)) << "mode " << j;
    // The fixed-interface eigenvalues are those of the interior alone, each once.
    EXPECT_EQ(r.mode_eigenvalues.size(), interior);
    EXPECT_LT(
        (r.K.bottomRightCorner(interior, interior).diagonal().real() - r.mode_eigenvalues).norm(),
        1e-9 * r.mode_eigenvalues.norm());
    EXPECT_EQ(nb, 6);
  }
}

TEST(CyclicCraigBampton, EigenvaluesApproachTheSectorsFromAboveAsModesAreAdded) {
  const Sector s = make_sector();
  for (const int h : {1, 2}) {  // complex fields (doubled real forms)
    SCOPED_TRACE("nodal diameter " + std::to_string(h));
    const CyclicSectorProblem p =
        cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, h);
    ASSERT_TRUE(p.doubled);
    const std::vector<int> b = masters(s, p);
    const int interior = static_cast<int>(p.independent.size() - b.size());
    const Eigen::VectorXd exact = sector_eigenvalues(p);
    constexpr int kCompared = 4;  // the lowest eigenvalues, each present from Guyan on (6 DOFs)
    std::vector<double> previous(kCompared, std::numeric_limits<double>::infinity());
    for (const int modes : {0, 2, 5, 10, 20, interior}) {
      SCOPED_TRACE("modes " + std::to_string(modes));
      const CyclicReducedSector r =
          cyclic_craig_bampton(p.K, p.M, p.doubled, h, b, with_modes(modes));
      ASSERT_TRUE(r.summary.ok()) << r.summary.message;
      ASSERT_EQ(r.mode_eigenvalues.size(), modes);
      const Eigen::VectorXd reduced = reduced_eigenvalues(r);
      for (int j = 0; j < kCompared; ++j) {
        // Rayleigh–Ritz: an upper bound, not increasing as the (nested) space grows.
        EXPECT_GE(reduced(j), exact(j) * (1 - 1e-10)) << "mode " << j;
        EXPECT_LE(reduced(j), previous[j] * (1 + 1e-10)) << "mode " << j;
        previous[j] = reduced(j);
      }
      if (modes == interior) {
        for (int j = 0; j < kCompared; ++j) EXPECT_NEAR(reduced(j), exact(j), 1e-9 * exact(j));
      }
    }
  }
}

TEST(CyclicCraigBampton, AStaticLoadOnTheMastersIsExactWithGuyanAndWithModes) {
  const Sector s = make_sector();
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const int h : {0, 1, 3}) {
    SCOPED_TRACE("nodal diameter " + std::to_string(h));
    const CyclicSectorProblem p =
        cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, h);
    const std::vector<int> b = masters(s, p);
    const Eigen::Index n = static_cast<Eigen::Index>(p.independent.size());
    const Eigen::Index nb = static_cast<Eigen::Index>(b.size());
    Eigen::VectorXcd f_b(nb);
    for (Eigen::Index k = 0; k < nb; ++k) f_b(k) = 1e6 * Complex(uniform(rng), uniform(rng));
    // The full sector: K_h u = f with f on the masters only.
    Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
    for (Eigen::Index k = 0; k < nb; ++k) f(b[static_cast<size_t>(k)]) = f_b(k);
    const Eigen::VectorXcd u = hermitian_stiffness(p).fullPivLu().solve(f);
    for (const int modes : {0, 4}) {
      SCOPED_TRACE("modes " + std::to_string(modes));
      const CyclicReducedSector r =
          cyclic_craig_bampton(p.K, p.M, p.doubled, h, b, with_modes(modes));
      ASSERT_TRUE(r.summary.ok()) << r.summary.message;
      Eigen::VectorXcd f_r = Eigen::VectorXcd::Zero(r.K.rows());
      f_r.head(nb) = f_b;
      const Eigen::VectorXcd q = r.K.fullPivLu().solve(f_r);
      for (Eigen::Index k = 0; k < nb; ++k) {
        EXPECT_LT(std::abs(q(k) - u(b[static_cast<size_t>(k)])), 1e-9 * u.cwiseAbs().maxCoeff())
            << "master DOF " << k;
      }
      EXPECT_LT((r.T * q - u).norm(), 1e-9 * u.norm());
    }
  }
}

TEST(CyclicCraigBampton, BadBoundariesAreRefused) {
  const Sector s = make_sector();
  const CyclicSectorProblem p = cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, 1);
  const int n = static_cast<int>(p.independent.size());
  const std::vector<int> outside{0, n};  // n: a DOF of the real form's second half
  EXPECT_THROW(cyclic_craig_bampton(p.K, p.M, p.doubled, 1, outside, with_modes(2)), InvalidInput);
  const std::vector<int> twice{3, 3};
  EXPECT_THROW(cyclic_craig_bampton(p.K, p.M, p.doubled, 1, twice, with_modes(2)), InvalidInput);
  const std::vector<int> ok{3};
  EXPECT_THROW(cyclic_craig_bampton(p.K, p.M, p.doubled, 1, ok, with_modes(n)), InvalidInput);
  // The real form's shortcut (half the constraint modes, the rest J times them) needs the
  // boundary {b, n + b}.
  CraigBamptonOptions paired_options = with_modes(2);
  paired_options.hermitian_real_form = true;
  const std::vector<int> unpaired{3, 4}, paired{3, n + 3};
  EXPECT_THROW(craig_bampton(p.K, p.M, {}, unpaired, paired_options), InvalidInput);
  EXPECT_TRUE(craig_bampton(p.K, p.M, {}, paired, paired_options).summary.ok());
}

}  // namespace
}  // namespace stickslip
