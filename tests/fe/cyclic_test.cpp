// Cyclic symmetry (fe/cyclic.h) against CalculiX's cyclic symmetry on the same sector, and against
// the whole ring, built here as one ordinary mesh: the
// frequencies of all nodal diameters of one sector, each 0 < h < N/2 counted twice, are the ring's
// frequencies; a sector mode repeated around the ring with its phase is a mode of the ring
// (residual of the ring's own K and M); bad boundaries name their nodes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "../ccx_dat.h"
#include "../cyclic_annulus.h"
#include "../required_tool.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "fe/cyclic.h"
#include "linalg/modal.h"

namespace stickslip {
namespace {

// The default annulus of cyclic_annulus.h: 2 elements in r, 1 in z.
constexpr int kRadial = 2, kAxial = 1;
using testing_cyclic::Annulus;
using testing_cyclic::annulus;

const IsotropicMaterial kSteel{.youngs_modulus = 2.1e11, .poisson_ratio = 0.3, .density = 7800};

void assemble(const Mesh& mesh, SparseMatrix* K, SparseMatrix* M) {
  assemble_stiffness_mass(mesh, kSteel, AssemblyOptions{}, K, M);
}

// Full DOFs of the nodes at the inner radius (clamped).
std::vector<int> inner_dofs(const Annulus& a) {
  std::vector<int> dofs;
  for (int k = 0; k <= kAxial; ++k)
    for (int j = 0; j < a.nj; ++j)
      for (int c = 0; c < 3; ++c) dofs.push_back(3 * a.node(0, j, k) + c);
  std::sort(dofs.begin(), dofs.end());
  return dofs;
}

std::vector<int> free_dofs(int ndof, const std::vector<int>& clamped) {
  std::vector<int> out;
  for (int d = 0; d < ndof; ++d)
    if (!std::binary_search(clamped.begin(), clamped.end(), d)) out.push_back(d);
  return out;
}

SparseMatrix select(const SparseMatrix& A, const std::vector<int>& keep) {
  Eigen::MatrixXd dense = Eigen::MatrixXd(A);
  Eigen::MatrixXd out(keep.size(), keep.size());
  for (size_t i = 0; i < keep.size(); ++i)
    for (size_t j = 0; j < keep.size(); ++j) out(i, j) = dense(keep[i], keep[j]);
  return out.sparseView();
}

struct Sector {
  Annulus a;
  SparseMatrix K, M;
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> clamped;
  CyclicSymmetry symmetry;
};

Sector sector(int N, int per_sector) {
  Sector s{annulus(N, per_sector, 1), {}, {}, {}, {}, {}};
  assemble(s.a.mesh, &s.K, &s.M);
  s.symmetry.sectors = N;
  std::vector<int> low, high;
  for (int k = 0; k <= kAxial; ++k)
    for (int i = 0; i <= kRadial; ++i) {
      low.push_back(s.a.node(i, 0, k));
      high.push_back(s.a.node(i, per_sector, k));
    }
  s.pairs = match_cyclic_boundaries(s.a.mesh, low, high, s.symmetry, 1e-9);
  s.clamped = inner_dofs(s.a);
  return s;
}

TEST(Cyclic, EveryNodalDiameterTogetherGivesTheWholeRingsFrequencies) {
  for (const int N : {6, 7}) {
    SCOPED_TRACE("N = " + std::to_string(N));
    const int per_sector = 2;
    const Sector s = sector(N, per_sector);
    std::vector<double> cyclic;
    for (int h = 0; 2 * h <= N; ++h) {
      const CyclicSectorProblem p = cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, h);
      const ModalResult r = dense_modes(p.K, p.M);
      ASSERT_TRUE(r.summary.ok());
      if (!p.doubled) {
        for (double l : r.eigenvalues) cyclic.push_back(l);
        continue;
      }
      // The real form holds each eigenvalue twice: consecutive pairs, equal.
      ASSERT_EQ(r.eigenvalues.size() % 2, 0);
      for (Eigen::Index j = 0; j < r.eigenvalues.size(); j += 2) {
        EXPECT_NEAR(r.eigenvalues(j), r.eigenvalues(j + 1), 1e-9 * r.eigenvalues(j + 1)) << h;
        // 0 < h < N/2: a double mode of the ring.
        cyclic.push_back(r.eigenvalues(j));
        cyclic.push_back(r.eigenvalues(j));
      }
    }
    std::sort(cyclic.begin(), cyclic.end());

    const Annulus ring = annulus(N, per_sector, N);
    SparseMatrix K, M;
    assemble(ring.mesh, &K, &M);
    const std::vector<int> keep = free_dofs(ring.mesh.num_dofs(), inner_dofs(ring));
    const ModalResult full = dense_modes(select(K, keep), select(M, keep));
    ASSERT_EQ(static_cast<size_t>(full.eigenvalues.size()), cyclic.size());
    for (size_t j = 0; j < cyclic.size(); ++j) {
      EXPECT_NEAR(cyclic[j], full.eigenvalues(static_cast<Eigen::Index>(j)),
                  1e-9 * full.eigenvalues(static_cast<Eigen::Index>(j)))
          << "mode " << j;
    }
  }
}

TEST(Cyclic, ASectorModeRepeatedWithItsPhaseIsAModeOfTheRing) {
  const int N = 6, per_sector = 2, h = 2;
  const Sector s = sector(N, per_sector);
  const CyclicSectorProblem p = cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, h);
  ASSERT_TRUE(p.doubled);
  const ModalResult r = dense_modes(p.K, p.M);
  const double lambda = r.eigenvalues(0);
  const Eigen::VectorXcd u = p.expand(r.modes.col(0));
  // Its high boundary is its low boundary rotated and phase-shifted.
  const Eigen::Matrix3d R = s.symmetry.rotation();
  const std::complex<double> phase = std::polar(1.0, 2 * M_PI * h / N);
  for (const auto& [lo, hi] : s.pairs) {
    const Eigen::Vector3cd expected = phase * (R.cast<std::complex<double>>() * u.segment<3>(3 * lo));
    EXPECT_LT((u.segment<3>(3 * hi) - expected).norm(), 1e-12 * u.norm());
  }
  // Sector s of the ring: the field rotated s times, with the phase e^{iφ s}.
  const Annulus ring = annulus(N, per_sector, N);
  Eigen::VectorXcd U = Eigen::VectorXcd::Zero(ring.mesh.num_dofs());
  Eigen::Matrix3d Rs = Eigen::Matrix3d::Identity();
  for (int sec = 0; sec < N; ++sec) {
    const std::complex<double> ph = std::polar(1.0, 2 * M_PI * h * sec / N);
    for (int k = 0; k <= kAxial; ++k)
      for (int j = 0; j < per_sector; ++j)
        for (int i = 0; i <= kRadial; ++i) {
          const int from = s.a.node(i, j, k), to = ring.node(i, sec * per_sector + j, k);
          U.segment<3>(3 * to) = ph * (Rs.cast<std::complex<double>>() * u.segment<3>(3 * from));
        }
    Rs = R * Rs;
  }
  SparseMatrix K, M;
  assemble(ring.mesh, &K, &M);
  const std::vector<int> keep = free_dofs(ring.mesh.num_dofs(), inner_dofs(ring));
  const Eigen::VectorXcd KU = K.cast<std::complex<double>>() * U, MU = M.cast<std::complex<double>>() * U;
  double residual = 0, scale = 0;
  for (int d : keep) {
    residual += std::norm(KU(d) - lambda * MU(d));
    scale += std::norm(KU(d));
  }
  EXPECT_LT(std::sqrt(residual), 1e-9 * std::sqrt(scale));
}

// CalculiX's own cyclic symmetry (*TIE, CYCLIC SYMMETRY + *CYCLIC SYMMETRY MODEL, *SELECT CYCLIC
// SYMMETRY MODES) on the same sector: the lowest frequencies of each nodal diameter. ccx refuses a
// clamped node on the dependent side, so the clamped inner nodes of the high boundary are left out
// of its tie (they are clamped either way).
TEST(Cyclic, EachNodalDiameterMatchesCalculixOnTheSameSector) {
  const bool have_ccx = std::system("command -v ccx > /dev/null 2>&1") == 0;
  STICKSLIP_REQUIRE_TOOL(have_ccx, "ccx (CalculiX)");
  const int N = 6, per_sector = 2;
  const Sector s = sector(N, per_sector);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("stickslip_cyclic_ccx_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    std::ofstream deck(dir / "sector.inp");
    deck.precision(17);
    const Mesh& m = s.a.mesh;
    deck << "*NODE\n";
    for (int n = 0; n < m.num_nodes(); ++n) {
      deck << m.node_ids[n] << ", " << m.coordinates(0, n) << ", " << m.coordinates(1, n) << ", "
           << m.coordinates(2, n) << "\n";
    }
    deck << "*ELEMENT, TYPE=C3D8, ELSET=ALL\n";
    for (int e = 0; e < m.num_elements(); ++e) {
      deck << m.element_ids[e];
      for (int n : m.element_nodes(e)) deck << ", " << m.node_ids[n];
      deck << "\n";
    }
    deck << "*NSET, NSET=INNER\n";
    for (size_t d = 0; d < s.clamped.size(); d += 3) deck << m.node_ids[s.clamped[d] / 3] << "\n";
    deck << "*SURFACE, NAME=LOW, TYPE=NODE\n";
    for (const auto& [lo, hi] : s.pairs) deck << m.node_ids[lo] << "\n";
    deck << "*SURFACE, NAME=HIGH, TYPE=NODE\n";
    for (const auto& [lo, hi] : s.pairs) {
      if (!std::binary_search(s.clamped.begin(), s.clamped.end(), 3 * hi)) deck << m.node_ids[hi] << "\n";
    }
    deck << "*MATERIAL, NAME=STEEL\n*ELASTIC\n" << kSteel.youngs_modulus << ", " << kSteel.poisson_ratio
         << "\n*DENSITY\n" << kSteel.density << "\n*SOLID SECTION, ELSET=ALL, MATERIAL=STEEL\n"
         << "*TIE, NAME=CYC, CYCLIC SYMMETRY\nHIGH, LOW\n"
         << "*CYCLIC SYMMETRY MODEL, N=" << N << ", TIE=CYC\n0., 0., 0., 0., 0., 1.\n"
         << "*BOUNDARY\nINNER, 1, 3\n*STEP\n*FREQUENCY\n6\n"
         << "*SELECT CYCLIC SYMMETRY MODES, NMIN=0, NMAX=" << N / 2 << "\n*END STEP\n";
  }
  const std::string command =
      "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i sector > ccx.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(dir / "sector.dat");
  std::stringstream text;
  text << in.rdbuf();
  const std::map<int, std::vector<double>> ccx = ccx_dat::cyclic_eigenvalues(text.str());
  ASSERT_EQ(ccx.size(), static_cast<size_t>(N / 2 + 1)) << text.str();
  for (const auto& [h, values] : ccx) {
    SCOPED_TRACE("nodal diameter " + std::to_string(h));
    const CyclicSectorProblem p = cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, h);
    const ModalResult r = dense_modes(p.K, p.M);
    std::vector<double> ours;
    for (Eigen::Index j = 0; j < r.eigenvalues.size(); j += p.doubled ? 2 : 1) ours.push_back(r.eigenvalues(j));
    // ccx: each eigenvalue twice; 7 significant digits printed.
    ASSERT_GE(values.size(), 6u);
    for (size_t j = 0; j < 3; ++j) {
      EXPECT_NEAR(values[2 * j], values[2 * j + 1], 1e-6 * values[2 * j]);
      EXPECT_NEAR(ours[j], values[2 * j], 2e-6 * values[2 * j]) << "mode " << j;
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(Cyclic, BoundariesThatDoNotMatchNameTheirNodes) {
  Sector s = sector(6, 2);
  std::vector<int> low, high;
  for (const auto& [lo, hi] : s.pairs) low.push_back(lo), high.push_back(hi);
  Mesh moved = s.a.mesh;
  moved.coordinates(2, high[1]) += 1e-3;
  try {
    match_cyclic_boundaries(moved, low, high, s.symmetry, 1e-6);
    FAIL() << "a moved high node was matched";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("low node " + std::to_string(moved.node_ids[low[1]])),
              std::string::npos)
        << e.what();
  }
  CyclicSymmetry wrong = s.symmetry;
  wrong.sectors = 5;  // 72° instead of 60°: nothing lands
  EXPECT_THROW(match_cyclic_boundaries(s.a.mesh, low, high, wrong, 1e-6), InvalidInput);
  high.pop_back();
  EXPECT_THROW(match_cyclic_boundaries(s.a.mesh, low, high, s.symmetry, 1e-6), InvalidInput);
  EXPECT_THROW(cyclic_sector_problem(s.K, s.M, s.pairs, s.clamped, s.symmetry, 4), InvalidInput);
}

}  // namespace
}  // namespace stickslip
