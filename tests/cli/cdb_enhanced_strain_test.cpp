// ANSYS SOLID185 with KEYOPT(2) = 3 (simplified enhanced strain: 9 enhanced modes against shear
// locking) is read as C3D8I, the Wilson–Taylor incompatible-mode brick with Taylor's modification,
// which for linear elasticity is that element. A coarse bar of such bricks written by the test as
// a CDB file (CDWRITE's layout), read by the CDB reader, assembled and solved under pure bending:
//  - against the closed form of pure bending of a prismatic bar (curvature κ = M / EI, the
//    anticlastic terms with ν included): u_x = -κ x z, u_y = ν κ y z, u_z = κ (x² + ν (z² - y²))/2
//    (y, z from the section's centre), which the incompatible modes contain on rectangular
//    bricks: every nodal displacement to round-off, so the tip deflection is M L² / (2 EI) of beam
//    theory on a 4 x 2 x 2 mesh (plain C3D8 gives a fraction of it);
//  - against CalculiX's C3D8I (ccx *STATIC, run by the test) on the same mesh and loads (equal on
//    parallelepipeds, where ccx's missing det J0/det J factor is 1), to ccx's 7 printed digits.
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "io/cdb_reader.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/SparseCholesky>

namespace {

using namespace stickslip::cli_test;
using stickslip::ElementType;

constexpr int kNx = 4, kNy = 2, kNz = 2;
constexpr double kL = 0.4, kB = 0.04, kH = 0.06;  // m: length (x), width (y), depth (z)
const stickslip::IsotropicMaterial kSteel{
    .youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
constexpr double kCurvature = 1e-3;  // 1/m

int node_id(int i, int j, int k) { return grid_node(kNx, kNy, i, j, k); }

std::string enhanced_strain_bar_cdb(int keyopt2) {
  std::ostringstream cdb;
  char buf[256];
  const int nodes = node_id(kNx, kNy, kNz), elements = kNx * kNy * kNz;
  cdb << "/PREP7\nET,1,185\nKEYOPT,1,2," << keyopt2 << "\nNBLOCK,6,SOLID," << nodes << "," << nodes
      << "\n(3i9,6e21.13e3)\n";
  for (int k = 0; k <= kNz; ++k)
    for (int j = 0; j <= kNy; ++j)
      for (int i = 0; i <= kNx; ++i) {
        std::snprintf(buf, sizeof buf, "%9d%9d%9d%21.13E%21.13E%21.13E\n", node_id(i, j, k), 0, 0,
                      kL * i / kNx, kB * j / kNy, kH * k / kNz);
        cdb << buf;
      }
  cdb << "N,R5.3,LOC,       -1,\nEBLOCK,19,SOLID," << elements << "," << elements << "\n(19i9)\n";
  int e = 1;
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) {
        std::snprintf(buf, sizeof buf, "%9d%9d%9d%9d%9d%9d%9d%9d%9d%9d%9d", 1, 1, 1, 1, 0, 0, 0, 0,
                      8, 0, e++);
        cdb << buf;
        for (int n : {node_id(i, j, k), node_id(i + 1, j, k), node_id(i + 1, j + 1, k),
                      node_id(i, j + 1, k), node_id(i, j, k + 1), node_id(i + 1, j, k + 1),
                      node_id(i + 1, j + 1, k + 1), node_id(i, j + 1, k + 1)}) {
          std::snprintf(buf, sizeof buf, "%9d", n);
          cdb << buf;
        }
        cdb << "\n";
      }
  cdb << "       -1\n";
  return cdb.str();
}

// The pure-bending problem on a mesh: supports that the exact field satisfies (u_x = 0 on x = 0;
// u_y = u_z = 0 at the section's centre there, u_y = 0 at a second node on y = B/2) and the end
// face x = L loaded by σ_xx = -E κ (z - H/2) as consistent nodal forces (bilinear faces:
// ∫ N_a z dz over [z0, z1] = h (2 z0 + z1) / 6 at z0, h (z0 + 2 z1) / 6 at z1).
struct Bending {
  std::vector<int> held;  // DOFs (3 · node index + direction)
  Eigen::VectorXd f;      // N
};

Bending pure_bending(const stickslip::Mesh& mesh) {
  std::vector<int> index_of(static_cast<size_t>(node_id(kNx, kNy, kNz) + 1), -1);
  for (int n = 0; n < mesh.num_nodes(); ++n) index_of[mesh.node_ids[n]] = n;
  const auto dof = [&](int i, int j, int k, int d) { return 3 * index_of[node_id(i, j, k)] + d; };
  Bending b;
  for (int k = 0; k <= kNz; ++k)
    for (int j = 0; j <= kNy; ++j) b.held.push_back(dof(0, j, k, 0));
  b.held.push_back(dof(0, kNy / 2, kNz / 2, 1));
  b.held.push_back(dof(0, kNy / 2, kNz / 2, 2));
  b.held.push_back(dof(0, kNy / 2, 0, 1));
  b.f = Eigen::VectorXd::Zero(mesh.num_dofs());
  const double E = kSteel.youngs_modulus, hy = kB / kNy, hz = kH / kNz;
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j) {
      const double z0 = hz * k - kH / 2, z1 = z0 + hz;
      const double at0 = -E * kCurvature * hz * (2 * z0 + z1) / 6 * hy / 2;
      const double at1 = -E * kCurvature * hz * (z0 + 2 * z1) / 6 * hy / 2;
      for (int dj : {0, 1}) {
        b.f(dof(kNx, j + dj, k, 0)) += at0;
        b.f(dof(kNx, j + dj, k + 1, 0)) += at1;
      }
    }
  return b;
}

Eigen::Vector3d exact_bending(const Eigen::Vector3d& x) {
  const double nu = kSteel.poisson_ratio, y = x(1) - kB / 2, z = x(2) - kH / 2;
  return {-kCurvature * x(0) * z, nu * kCurvature * y * z,
          kCurvature / 2 * (x(0) * x(0) + nu * (z * z - y * y))};
}

Eigen::VectorXd solve(const stickslip::Mesh& mesh, const Bending& b) {
  stickslip::SparseMatrix K;
  stickslip::assemble_stiffness_mass(mesh, kSteel, {}, &K, nullptr);
  const stickslip::DofMap map(mesh.num_dofs(), b.held);
  Eigen::SimplicialLDLT<stickslip::SparseMatrix> ldlt(map.restrict(K));
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  return map.expand(Eigen::VectorXd(ldlt.solve(map.restrict_load(b.f))));
}

TEST(CdbEnhancedStrain, Keyopt3BarBendsExactlyAndAsCalculixC3D8I) {
  std::istringstream in(enhanced_strain_bar_cdb(3));
  const stickslip::Mesh mesh = stickslip::read_cdb(in, "bar.cdb");
  for (ElementType t : mesh.element_types) ASSERT_EQ(t, ElementType::kC3D8I);
  const Bending b = pure_bending(mesh);
  const Eigen::VectorXd u = solve(mesh, b);
  double scale = 0.0, error = 0.0;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d exact = exact_bending(mesh.coordinates.col(n));
    scale = std::max(scale, exact.lpNorm<Eigen::Infinity>());
    error = std::max(error, (u.segment<3>(3 * n) - exact).lpNorm<Eigen::Infinity>());
  }
  // A sparse solve of a small, well-conditioned system: round-off only.
  constexpr double kRoundOff = 1e-9;
  EXPECT_LT(error, kRoundOff * scale);
  // Beam theory: tip deflection M L² / (2 EI) = κ L² / 2 on the neutral axis.
  int tip = 0;
  for (int n = 0; n < mesh.num_nodes(); ++n) tip = mesh.node_ids[n] == node_id(kNx, 1, 1) ? n : tip;
  EXPECT_NEAR(u(3 * tip + 2), kCurvature * kL * kL / 2, kRoundOff * scale);

  // Plain full integration (C3D8) on the same mesh locks in shear: far from the closed form.
  stickslip::Mesh c3d8 = mesh;
  for (ElementType& t : c3d8.element_types) t = ElementType::kC3D8;
  const Eigen::VectorXd u8 = solve(c3d8, b);
  EXPECT_LT(u8(3 * tip + 2), 0.9 * kCurvature * kL * kL / 2);

  // CalculiX's C3D8I on the same mesh, supports and loads.
  const fs::path dir = fresh_dir("cdb_enhanced_strain");
  {
    std::ofstream inp(dir / "job.inp");
    inp.precision(17);
    inp << "*NODE, NSET=NALL\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      inp << mesh.node_ids[n] << ", " << mesh.coordinates(0, n) << ", " << mesh.coordinates(1, n)
          << ", " << mesh.coordinates(2, n) << "\n";
    }
    inp << "*ELEMENT, TYPE=C3D8I, ELSET=EALL\n";
    for (int e = 0; e < mesh.num_elements(); ++e) {
      inp << mesh.element_ids[e];
      for (int n : mesh.element_nodes(e)) inp << ", " << mesh.node_ids[n];
      inp << "\n";
    }
    inp << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
           "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*STATIC\n*BOUNDARY\n";
    for (int d : b.held)
      inp << mesh.node_ids[d / 3] << ", " << d % 3 + 1 << ", " << d % 3 + 1 << "\n";
    inp << "*CLOAD\n";
    for (int d = 0; d < b.f.size(); ++d) {
      if (b.f(d) != 0.0) inp << mesh.node_ids[d / 3] << ", " << d % 3 + 1 << ", " << b.f(d) << "\n";
    }
    inp << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
  }
  ASSERT_EQ(shell("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job", dir / "ccx.log"), 0)
      << slurp(dir / "ccx.log");
  // The .dat's displacement block: "node ux uy uz" lines after its "displacements" header.
  std::istringstream dat(slurp(dir / "job.dat"));
  std::string line;
  bool block = false;
  int rows = 0;
  double ccx_error = 0.0;
  while (std::getline(dat, line)) {
    if (line.find("displacements") != std::string::npos) {
      block = true;
      continue;
    }
    std::istringstream s(line);
    int id = 0;
    double v[3];
    if (!block || !(s >> id >> v[0] >> v[1] >> v[2])) continue;
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (mesh.node_ids[n] != id) continue;
      for (int d = 0; d < 3; ++d) ccx_error = std::max(ccx_error, std::abs(v[d] - u(3 * n + d)));
      ++rows;
    }
  }
  EXPECT_EQ(rows, mesh.num_nodes()) << slurp(dir / "job.dat");
  // ccx prints 7 significant digits (E13.6).
  constexpr double kCcxPrintTolerance = 1e-5;
  EXPECT_LT(ccx_error, kCcxPrintTolerance * scale);
  std::printf(
      "[ SOLID185 KEYOPT(2)=3 ] pure bending: max error %.2e of %.3e m (closed form); "
      "ccx C3D8I: max difference %.2e m; C3D8 tip %.3f of beam theory\n",
      error, scale, ccx_error, u8(3 * tip + 2) / (kCurvature * kL * kL / 2));
  fs::remove_all(dir);
}

}  // namespace
