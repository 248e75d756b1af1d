// The recovery of a cyclic sector under engine-order excitation (recovery/cyclic_recovery.h)
// against the whole ring solved as one body by DirectRecovery (tests/bladed_ring.h: 6 shrouded
// blades on a clamped ring, 468 DOFs): sector s of the ring loaded with sector 0's loads rotated
// by R^s and times e^{i s σ_k}. Every harmonic's displacement, nodal stress and reaction of every
// sector of the ring equals the annulus made from the sector's (annulus_vectors, annulus_tensors,
// fold_boundary_residual, average_boundary_stresses), for engine orders reaching diameters 0, 1,
// 2, 3 = N/2 and the conjugates of 1 and 2.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "../bladed_ring.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "fe/cyclic.h"
#include "fe/dof_map.h"
#include "fe/stress.h"
#include "recovery/cyclic_recovery.h"
#include "recovery/harmonic_response.h"

namespace stickslip {
namespace {

using testing_cyclic::bladed_ring;
using testing_cyclic::BladedRing;
using Complex = std::complex<double>;

constexpr int kN = 6;
const IsotropicMaterial kSteel{.youngs_modulus = 2.1e11, .poisson_ratio = 0.3, .density = 7800};
const RayleighDamping kDamping{.alpha = 20.0, .beta = 2.0e-7};

Eigen::Matrix3d rotation(int s) {
  return Eigen::AngleAxisd(2 * std::numbers::pi * s / kN, Eigen::Vector3d::UnitZ())
      .toRotationMatrix();
}

// Sector-0 loads (full DOFs of the sector) per harmonic: a shroud node, a free node of the low
// cyclic boundary and a blade node; harmonic 0 real.
Eigen::MatrixXcd sector_loads(const BladedRing& s, const std::vector<int>& harmonics) {
  Eigen::MatrixXcd F = Eigen::MatrixXcd::Zero(s.mesh.num_dofs(), harmonics.size());
  const int nodes[3] = {s.forced(0), s.node(0, 1, 0, 1), s.node(0, 3, 0, 0)};
  for (size_t j = 0; j < harmonics.size(); ++j) {
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) {
        const double re = 100.0 * (1 + a + 2 * c) * (c == 1 ? -1 : 1);
        const double im = harmonics[j] == 0 ? 0.0 : 37.0 * (a - c + 0.5) * harmonics[j];
        F(3 * nodes[a] + c, static_cast<Eigen::Index>(j)) = Complex(re, im);
      }
    }
  }
  return F;
}

struct Fixture {
  BladedRing ring = bladed_ring(kN, kN), sector = bladed_ring(kN, 1);
  SparseMatrix Kr, Mr, Ks, Ms;
  CyclicSymmetry symmetry;
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> clamped;  // sector's full DOFs
  Fixture() {
    assemble_stiffness_mass(ring.mesh, kSteel, AssemblyOptions{}, &Kr, &Mr);
    assemble_stiffness_mass(sector.mesh, kSteel, AssemblyOptions{}, &Ks, &Ms);
    symmetry.sectors = kN;
    pairs =
        match_cyclic_boundaries(sector.mesh, sector.ring_low(), sector.ring_high(), symmetry, 1e-9);
    for (int node : sector.clamped_nodes())
      for (int c = 0; c < 3; ++c) clamped.push_back(3 * node + c);
  }
  // The ring node of sector s at the sector's node n (the same generator's key).
  int ring_node(int s, int n) const {
    for (const auto& [key, index] : sector.nodes) {
      if (index == n) {
        const auto [s0, level, jj, k] = key;
        return ring.node(s, level, jj, k);
      }
    }
    return -1;
  }
};

const Fixture& fixture() {
  static const Fixture* f = new Fixture;
  return *f;
}

// D x − F of a full body, per harmonic column.
Eigen::MatrixXcd residual(const SparseMatrix& K, const SparseMatrix& M, const Eigen::MatrixXcd& x,
                          const Eigen::MatrixXcd& F, const std::vector<int>& harmonics,
                          double omega) {
  Eigen::MatrixXcd r(x.rows(), x.cols());
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    const double w = harmonics[static_cast<size_t>(j)] * omega;
    const Eigen::VectorXcd Kx = K.cast<Complex>() * x.col(j), Mx = M.cast<Complex>() * x.col(j);
    r.col(j) =
        Kx - w * w * Mx + Complex(0, w) * (kDamping.alpha * Mx + kDamping.beta * Kx) - F.col(j);
  }
  return r;
}

class CyclicRecovery : public ::testing::TestWithParam<int> {};

TEST_P(CyclicRecovery, SectorEqualsTheWholeRingSolvedAsOneBodyInEverySector) {
  const int eo = GetParam();
  const Fixture& f = fixture();
  const std::vector<int> harmonics{0, 1, 2, 3};
  const double omega = 2 * std::numbers::pi * 1105.0;
  const Eigen::MatrixXcd Fs = sector_loads(f.sector, harmonics);
  // The ring: sector s's loads R^s F e^{i s σ_k}.
  Eigen::MatrixXcd Fr = Eigen::MatrixXcd::Zero(f.ring.mesh.num_dofs(), 4);
  for (int s = 0; s < kN; ++s) {
    for (int n = 0; n < f.sector.mesh.num_nodes(); ++n) {
      if (Fs.middleRows(3 * n, 3).norm() == 0) continue;
      for (int j = 0; j < 4; ++j) {
        const Complex phase = std::polar(1.0, 2 * std::numbers::pi * harmonics[j] * eo * s / kN);
        Fr.col(j).segment<3>(3 * f.ring_node(s, n)) +=
            phase * (rotation(s).cast<Complex>() * Fs.col(j).segment<3>(3 * n));
      }
    }
  }
  const DofMap ring_dofs = DofMap::from_nodes(f.ring.mesh.num_nodes(), f.ring.clamped_nodes());
  const DirectRecovery ring(f.Kr, f.Mr, ring_dofs, kDamping);
  ASSERT_TRUE(ring.ok()) << ring.message();
  RecoverySummary summary;
  const Eigen::MatrixXcd xr = harmonic_response(ring, Fr, harmonics, omega, &summary);
  ASSERT_TRUE(summary.ok()) << summary.message;

  const CyclicSectorRecovery sector(f.Ks, f.Ms, f.pairs, f.clamped, f.symmetry, eo, kDamping,
                                    harmonics);
  ASSERT_TRUE(sector.ok()) << sector.message();
  const Eigen::MatrixXcd xs = sector.solve(Fs, harmonics, omega, &summary);
  ASSERT_TRUE(summary.ok()) << summary.message;
  // Displacements of every sector.
  const Eigen::MatrixXcd xa = annulus_vectors(xs, harmonics, f.symmetry, eo);
  const int n = f.sector.mesh.num_nodes();
  double worst = 0;
  for (int s = 0; s < kN; ++s) {
    for (int a = 0; a < n; ++a) {
      worst = std::max(worst,
                       (xa.middleRows(3 * (s * n + a), 3) - xr.middleRows(3 * f.ring_node(s, a), 3))
                           .cwiseAbs()
                           .maxCoeff());
    }
  }
  EXPECT_GT(xr.cwiseAbs().maxCoeff(), 0.0);
  // Measured: 2e-11 to 3.3e-11 (harmonic 1, 1105 Hz, is near a mode: its solve's round-off).
  EXPECT_LT(worst / xr.cwiseAbs().maxCoeff(), 1e-9) << "displacement";
  // Nodal stresses (averaged across the cyclic boundary as in the ring).
  const NodalStressOperator ring_stress(f.ring.mesh, kSteel, AssemblyOptions{});
  const NodalStressOperator sector_stress(f.sector.mesh, kSteel, AssemblyOptions{});
  const std::vector<ComplexStressMatrix> Sr = ring_stress.apply(xr);
  std::vector<ComplexStressMatrix> Ss = sector_stress.apply(xs);
  sector.average_boundary_stresses(Ss, harmonics, elements_at_nodes(f.sector.mesh));
  const std::vector<ComplexStressMatrix> Sa = annulus_tensors(Ss, harmonics, f.symmetry, eo);
  for (size_t j = 0; j < harmonics.size(); ++j) {
    double diff = 0;
    for (int s = 0; s < kN; ++s) {
      for (int a = 0; a < n; ++a) {
        diff = std::max(
            diff, (Sa[j].col(s * n + a) - Sr[j].col(f.ring_node(s, a))).cwiseAbs().maxCoeff());
      }
    }
    EXPECT_GT(Sr[j].cwiseAbs().maxCoeff(), 0.0);
    EXPECT_LT(diff / Sr[j].cwiseAbs().maxCoeff(), 1e-9) << "stress, harmonic " << harmonics[j];
  }
  // Reactions at sector 0's clamped nodes (a low-boundary node's share from the previous sector).
  const Eigen::MatrixXcd rr = residual(f.Kr, f.Mr, xr, Fr, harmonics, omega);
  Eigen::MatrixXcd rs = residual(f.Ks, f.Ms, xs, Fs, harmonics, omega);
  sector.fold_boundary_residual(rs, harmonics);
  double reaction = 0, largest = 0;
  int held = 0;
  for (int node : f.sector.clamped_nodes()) {
    if (sector.is_high(node)) continue;
    ++held;
    reaction =
        std::max(reaction, (rs.middleRows(3 * node, 3) - rr.middleRows(3 * f.ring_node(0, node), 3))
                               .cwiseAbs()
                               .maxCoeff());
    largest = std::max(largest, rr.middleRows(3 * f.ring_node(0, node), 3).cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(held, 6);
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(reaction / largest, 1e-9) << "reactions";  // measured 7e-12 to 1.6e-11
}

// EO 1: diameters 0, 1, 2, 3; EO 2: 0, 2, conj 2, 0; EO 4: 0, conj 2, 2, 0; EO 5: 0, conj 1,
// conj 2, 3.
INSTANTIATE_TEST_SUITE_P(EngineOrders, CyclicRecovery, ::testing::Values(1, 2, 4, 5));

TEST(CyclicRecoveryAnnulus, MeshIsTheSectorRotatedNTimesWithDistinctIds) {
  const Fixture& f = fixture();
  const Mesh a = annulus_mesh(f.sector.mesh, f.symmetry);
  const int n = f.sector.mesh.num_nodes();
  ASSERT_EQ(a.num_nodes(), kN * n);
  ASSERT_EQ(a.num_elements(), kN * f.sector.mesh.num_elements());
  EXPECT_NO_THROW(check_mesh(a));
  double worst = 0;
  for (int s = 0; s < kN; ++s) {
    for (int node = 0; node < n; ++node) {
      worst = std::max(worst, (a.coordinates.col(s * n + node) -
                               f.ring.mesh.coordinates.col(f.ring_node(s, node)))
                                  .norm());
      EXPECT_EQ(a.node_ids[s * n + node], f.sector.mesh.node_ids[node] + s * 100);  // ids <= 36
    }
  }
  EXPECT_LT(worst, 1e-15);
  // Scalars repeat; a vector field of diameter h closes on itself after N sectors.
  const Eigen::MatrixXd v = Eigen::MatrixXd::Random(2, n);
  const Eigen::MatrixXd t = annulus_scalars(v, kN);
  EXPECT_EQ(t.cols(), kN * n);
  EXPECT_EQ(t.middleCols(3 * n, n), v);
}

TEST(CyclicRecoveryAnnulus, AHarmonicNotSetUpIsRefused) {
  const Fixture& f = fixture();
  const CyclicSectorRecovery r(f.Ks, f.Ms, f.pairs, f.clamped, f.symmetry, 1, kDamping,
                               std::vector<int>{0, 1});
  ASSERT_TRUE(r.ok()) << r.message();
  // Harmonic 2 of EO 1 is diameter 2, which was not set up.
  EXPECT_THROW(
      r.solve(Eigen::MatrixXcd::Zero(f.sector.mesh.num_dofs(), 1), std::vector<int>{2}, 1000.0),
      InvalidInput);
  EXPECT_THROW(r.solve(Eigen::MatrixXcd::Zero(3, 1), std::vector<int>{1}, 1000.0), InvalidInput);
}

}  // namespace
}  // namespace stickslip
