// C3D8R (one-point brick with CalculiX's hourglass stiffness) against CalculiX 2.20's C3D8R on the
// same decks, run by the tests:
//  - the stiffness and mass matrices of a skewed bar (every element the same parallelepiped, not
//    rectangular), clamped at x = 0, entry by entry against ccx's stored matrices
//    (*FREQUENCY, SOLVER=MATRIXSTORAGE, 14 printed digits);
//  - a cantilever of C3D8R under a tip load (*STATIC): every nodal displacement to ccx's printed
//    digits; bending through the thickness is carried by the hourglass stiffness here, so the
//    factor 0.0005 E and the base vectors are what this compares;
//  - a smoothly distorted bar: ccx orthogonalises its hourglass vectors against the z field only
//    (element.h), stickslip against x, y and z (Flanagan and Belytschko), so on non-parallelepiped
//    elements the two differ, by the gap printed here; ccx's stiffness then resists a rigid
//    rotation of a free element, stickslip's does not.
// The frequencies of the straight bar are in calculix_modal_test.cpp (C3D8R case).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "../ccx_dat.h"
#include "../required_tool.h"
#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/element.h"
#include "io/inp_reader.h"
#include "validation_support.h"

namespace stickslip::validation {
namespace {

// A skew with det A > 0 and no two columns parallel: every box cell becomes the same
// non-rectangular parallelepiped.
Eigen::Matrix3d skew() {
  Eigen::Matrix3d A;
  A << 1.0, 0.3, -0.2, 0.1, 1.1, 0.25, -0.15, 0.2, 0.9;
  return A;
}

// The deck as stickslip reads it: written to a file and read back, so both codes see the same
// printed coordinates.
Mesh read_deck(const std::string& deck, const std::string& job) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("stickslip_" + std::to_string(getpid()) + "_" + job + ".inp");
  std::ofstream(path) << deck;
  Mesh mesh = read_inp(path.string());
  std::filesystem::remove(path);
  return mesh;
}

IsotropicMaterial material(const Steel& steel) {
  return {steel.youngs_modulus, steel.poisson_ratio, steel.density};
}

Mesh skewed_bar(double distortion) {
  BoxOptions box;
  box.type = ElementType::kC3D8R;
  box.nx = 6;
  box.ny = 2;
  box.nz = 2;
  box.distortion = distortion;
  Mesh mesh = make_box_mesh(box);
  mesh.coordinates = skew() * mesh.coordinates;
  return mesh;
}

// max |ours − ccx's| over ccx's entries, relative to ccx's largest entry; ccx's DOFs mapped onto
// ours by (node id, direction).
double matrix_gap(const Mesh& mesh, const SparseMatrix& ours, const SparseMatrix& theirs,
                  const std::vector<std::pair<int, int>>& dofs) {
  std::map<int, int> index_of_id;
  for (int n = 0; n < mesh.num_nodes(); ++n) index_of_id[mesh.node_ids[n]] = n;
  std::vector<int> ours_of(dofs.size());
  for (size_t i = 0; i < dofs.size(); ++i) {
    ours_of[i] = 3 * index_of_id.at(dofs[i].first) + dofs[i].second;
  }
  const Eigen::MatrixXd O(ours), T(theirs);
  double gap = 0.0;
  for (size_t i = 0; i < dofs.size(); ++i) {
    for (size_t j = 0; j < dofs.size(); ++j) {
      const double d =
          O(ours_of[i], ours_of[j]) - T(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      gap = std::max(gap, std::abs(d));
    }
  }
  return gap / T.cwiseAbs().maxCoeff();
}

TEST(CalculixC3D8R, StiffnessAndMassOfASkewedBarEqualCalculixs) {
  STICKSLIP_REQUIRE_TOOL(find_ccx(), "ccx (CalculiX)");
  const Steel steel;
  const std::string deck = calculix_matrix_deck(skewed_bar(0.0), steel);
  const Mesh mesh = read_deck(deck, "c3d8r_skewed");
  const CalculixMatrices ccx = run_calculix_matrices(deck, "c3d8r_skewed");
  AssemblyOptions options;
  options.mass_integration = MassIntegration::kStiffnessRule;  // CalculiX's one-point mass
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, material(steel), options, &K, &M);
  ASSERT_EQ(ccx.dofs.size(), static_cast<size_t>(mesh.num_dofs() - 3 * 9));  // 3x3 nodes clamped
  // ccx prints 14 significant digits: entries agree to that, relative to the largest.
  constexpr double kPrintedDigits = 1e-12;
  const double k_gap = matrix_gap(mesh, K, ccx.K, ccx.dofs);
  const double m_gap = matrix_gap(mesh, M, ccx.M, ccx.dofs);
  EXPECT_LT(k_gap, kPrintedDigits);
  EXPECT_LT(m_gap, kPrintedDigits);
  std::printf("[ CalculiX ] C3D8R skewed bar: max |K - K_ccx| / max|K_ccx| = %.1e, M: %.1e\n",
              k_gap, m_gap);
}

TEST(CalculixC3D8R, CantileverUnderATipLoadDeflectsAsCalculixs) {
  STICKSLIP_REQUIRE_TOOL(find_ccx(), "ccx (CalculiX)");
  const Steel steel;
  const Mesh generated = skewed_bar(0.0);
  // Tip load: 1 kN in z shared by the nodes of the end face (largest x of the straight box,
  // i.e. the nodes whose pre-skew x is the bar's length).
  const Eigen::Matrix3d inverse = skew().inverse();
  std::vector<int> tip;
  for (int n = 0; n < generated.num_nodes(); ++n) {
    if (std::abs((inverse * generated.coordinates.col(n))(0) - BoxOptions().a) < 1e-9) {
      tip.push_back(n);
    }
  }
  ASSERT_EQ(tip.size(), 9u);
  constexpr double kLoad = 1000.0;  // N
  std::ostringstream step;
  step.precision(17);
  step << "*CLOAD\n";
  for (int n : tip) step << generated.node_ids[n] << ", 3, " << kLoad / tip.size() << "\n";
  step << "*NODE PRINT, NSET=NALL\nU\n";
  const std::string extra =
      "*NSET, NSET=NALL, GENERATE\n1, " + std::to_string(generated.num_nodes()) + ", 1\n";
  const std::string deck = calculix_static_deck(generated, steel, step.str(), extra);
  const Mesh mesh = read_deck(deck, "c3d8r_cantilever");
  const auto ccx = ccx_dat::displacements(run_calculix_dat(deck, "c3d8r_cantilever"));
  ASSERT_EQ(ccx.size(), static_cast<size_t>(mesh.num_nodes()));

  SparseMatrix K;
  assemble_stiffness_mass(mesh, material(steel), {}, &K, nullptr);
  const DofMap map = DofMap::from_nodes(mesh.num_nodes(), mesh.node_sets.at("FIX"));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (int n : tip) f(3 * n + 2) = kLoad / tip.size();
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(map.restrict(K));
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd u = map.expand(Eigen::VectorXd(ldlt.solve(map.restrict_load(f))));

  double scale = 0.0, gap = 0.0;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const auto& v = ccx.at(mesh.node_ids[n]);
    for (int d = 0; d < 3; ++d) {
      scale = std::max(scale, std::abs(v[static_cast<size_t>(d)]));
      gap = std::max(gap, std::abs(u(3 * n + d) - v[static_cast<size_t>(d)]));
    }
  }
  // ccx prints 7 significant digits (E13.6): 5e-7 of each value, at most of the largest.
  constexpr double kPrintedDigits = 1e-6;
  EXPECT_LT(gap, kPrintedDigits * scale);
  std::printf("[ CalculiX ] C3D8R cantilever: max |u - u_ccx| = %.2e m of %.3e m\n", gap, scale);
}

// One free distorted brick (no two faces parallel): ccx's stored stiffness against ours. Both
// leave translations free; a rigid rotation costs nothing in ours (the hourglass vectors are
// orthogonal to every linear field) but does in ccx's. Swapping, in the test, our hourglass
// term c Σ γγᵀ for one with ccx's vectors γ_z = h − b̄_z (zᵀh) (b̄ from the public shape
// functions, c = 0.0005 E V Σ b̄²) gives ccx's matrix: the projection is the whole difference.
TEST(CalculixC3D8R, OnADistortedBrickOnlyCalculixsHourglassStiffnessResistsARigidRotation) {
  STICKSLIP_REQUIRE_TOOL(find_ccx(), "ccx (CalculiX)");
  const std::string deck =
      "*NODE\n1, 0, 0, 0\n2, 1.1, 0.1, -0.05\n3, 1.2, 0.9, 0.1\n4, -0.1, 1, 0\n"
      "5, 0.05, -0.1, 0.8\n6, 1, 0, 1.1\n7, 1.1, 1.2, 0.9\n8, 0.1, 0.9, 1\n"
      "*ELEMENT, TYPE=C3D8R, ELSET=EALL\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
      "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
      "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n1\n"
      "*END STEP\n";
  const Mesh mesh = read_deck(deck, "c3d8r_one");
  const CalculixMatrices ccx = run_calculix_matrices(deck, "c3d8r_one");
  ASSERT_EQ(ccx.dofs.size(), 24u);
  const Steel steel;
  SparseMatrix K;
  assemble_stiffness_mass(mesh, material(steel), {}, &K, nullptr);
  // Rigid motions at ccx's DOFs and at ours (node n of the mesh has id n + 1 here).
  Eigen::VectorXd translation(24), rotation(24), ours_rotation(24);
  for (size_t i = 0; i < 24; ++i) {
    const auto [id, d] = ccx.dofs[i];
    const Eigen::Vector3d x = mesh.coordinates.col(id - 1);
    translation(static_cast<Eigen::Index>(i)) = d == 0 ? 1.0 : 0.0;
    rotation(static_cast<Eigen::Index>(i)) = Eigen::Vector3d(-x(1), x(0), 0.0)(d);  // about z
  }
  for (int n = 0; n < 8; ++n) {
    const Eigen::Vector3d x = mesh.coordinates.col(n);
    ours_rotation.segment<3>(3 * n) = Eigen::Vector3d(-x(1), x(0), 0.0);
  }
  const double k_ccx = Eigen::MatrixXd(ccx.K).cwiseAbs().maxCoeff();
  const double k_ours = Eigen::MatrixXd(K).cwiseAbs().maxCoeff();
  const double ccx_translation = (ccx.K * translation).lpNorm<Eigen::Infinity>() / k_ccx;
  const double ccx_rotation = (ccx.K * rotation).lpNorm<Eigen::Infinity>() / k_ccx;
  const double ours = (K * ours_rotation).lpNorm<Eigen::Infinity>() / k_ours;
  constexpr double kPrintedDigits = 1e-12;  // ccx's 14 digits, summed over 24 entries
  EXPECT_LT(ccx_translation, kPrintedDigits);
  EXPECT_LT(ours, kPrintedDigits);
  // ccx's hourglass stiffness, 0.0005 E-scaled, against a rotation of a brick distorted by ~10 %.
  EXPECT_GT(ccx_rotation, 1e-4);
  const double k_gap = matrix_gap(mesh, K, ccx.K, ccx.dofs);

  // b̄ = (1/V) ∫ ∂N/∂x dV with the 2x2x2 rule (exact for the trilinear brick), V likewise.
  const Eigen::Matrix3Xd X = mesh.coordinates;
  const Eigen::Matrix3Xd P = integration_points(ElementType::kC3D8);
  const Eigen::VectorXd w = integration_weights(ElementType::kC3D8);
  Eigen::Matrix<double, 3, 8> bbar = Eigen::Matrix<double, 3, 8>::Zero();
  double V = 0.0;
  for (int g = 0; g < P.cols(); ++g) {
    Eigen::VectorXd N;
    Eigen::Matrix3Xd dN;
    shape_functions(ElementType::kC3D8, P.col(g), N, dN);
    const Eigen::Matrix3d J = dN * X.transpose();
    bbar += w(g) * J.determinant() * (J.inverse() * dN);
    V += w(g) * J.determinant();
  }
  bbar /= V;
  const Eigen::Matrix3Xd corners = natural_node_coordinates(ElementType::kC3D8);
  Eigen::Matrix<double, 8, 4> h;
  for (int a = 0; a < 8; ++a) {
    const Eigen::Vector3d c = corners.col(a);
    h.row(a) << c(1) * c(2), c(0) * c(2), c(0) * c(1), c(0) * c(1) * c(2);
  }
  const Eigen::Matrix<double, 8, 4> gamma = h - bbar.transpose() * (X * h);
  const Eigen::Matrix<double, 8, 4> gamma_z = h - bbar.row(2).transpose() * (X.row(2) * h);
  const double c = 0.0005 * steel.youngs_modulus * V * bbar.squaredNorm();
  const Eigen::Matrix<double, 8, 8> swap =
      c * (gamma_z * gamma_z.transpose() - gamma * gamma.transpose());
  Eigen::MatrixXd K_as_ccx = Eigen::MatrixXd(K);
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      for (int d = 0; d < 3; ++d) K_as_ccx(3 * a + d, 3 * b + d) += swap(a, b);
  const double swapped_gap = matrix_gap(mesh, SparseMatrix(K_as_ccx.sparseView()), ccx.K, ccx.dofs);
  EXPECT_LT(swapped_gap, kPrintedDigits);
  EXPECT_GT(k_gap, 1e3 * kPrintedDigits);
  std::printf(
      "[ CalculiX ] C3D8R distorted brick: |K_ccx r| / max|K_ccx| = %.1e for a rigid rotation "
      "r (ours %.1e); max |K - K_ccx| / max|K_ccx| = %.1e, %.1e with ccx's z-only hourglass "
      "vectors\n",
      ccx_rotation, ours, k_gap, swapped_gap);
}

}  // namespace
}  // namespace stickslip::validation
