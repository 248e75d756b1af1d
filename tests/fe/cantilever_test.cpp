// Cantilever under a tip shear load against Timoshenko beam theory: incompatible-mode hexahedra
// are accurate on a coarse mesh, fully integrated ones lock (shear locking) and converge only
// under refinement.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/SparseCholesky>

#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/element.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
constexpr double kL = 1.0, kH = 0.1, kB = 0.1;  // length x, depth y, width z (m)
constexpr double kP = 1000.0;                   // tip load along +y (N)

// Timoshenko: d = P L^3 / (3 E I) + P L / (kappa G A), kappa = 10 (1 + nu) / (12 + 11 nu)
// (Cowper's shear coefficient of a rectangle).
double timoshenko_tip_deflection(const IsotropicMaterial& material = kSteel) {
  const double E = material.youngs_modulus, nu = material.poisson_ratio;
  const double I = kB * kH * kH * kH / 12.0, A = kB * kH;
  const double kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
  return kP * kL * kL * kL / (3.0 * E * I) + kP * kL / (kappa * shear_modulus(material) * A);
}

// Tip deflection (u_y at the centre of the tip face) of an nx x ny x nz mesh clamped at x = 0,
// with a uniform shear traction P/(b h) on x = L applied as consistent nodal forces.
double fe_tip_deflection(ElementType type, int nx, int ny, int nz,
                         const IsotropicMaterial& material = kSteel) {
  const Eigen::Vector3d size(kL, kH, kB);
  const Mesh mesh = testing::box_mesh(type, nx, ny, nz, size);
  SparseMatrix K;
  assemble_stiffness_mass(mesh, material, {}, &K, nullptr);
  std::vector<int> clamped;
  int tip_centre = -1;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d x = mesh.coordinates.col(n);
    if (std::abs(x(0)) < 1e-12) clamped.push_back(n);
    if ((x - Eigen::Vector3d(kL, kH / 2, kB / 2)).norm() < 1e-12) tip_centre = n;
  }
  EXPECT_GE(tip_centre, 0);
  // Consistent loads: f_a = t * integral over the face xi = +1 of N_a dA (3x3 Gauss, exact).
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_dofs());
  const double traction = kP / (kH * kB);
  const double gp[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  Eigen::VectorXd N;
  Eigen::Matrix3Xd dN;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto nodes = mesh.element_nodes(e);
    if (std::abs(mesh.coordinates(0, nodes[1]) - kL) > 1e-12) continue;  // node 2 at xi = +1
    const double face_area = (kH / ny) * (kB / nz);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        shape_functions(type, Eigen::Vector3d(1.0, gp[i], gp[j]), N, dN);
        for (size_t a = 0; a < nodes.size(); ++a) {
          f(dof_of(nodes[a], 1)) += traction * N(a) * gw[i] * gw[j] * face_area / 4.0;
        }
      }
    }
  }
  EXPECT_NEAR(f.sum(), kP, 1e-9 * kP);
  const DofMap map = DofMap::from_nodes(mesh.num_nodes(), clamped);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(map.restrict(K));
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd u = map.expand(Eigen::VectorXd(ldlt.solve(map.restrict(f))));
  return u(dof_of(tip_centre, 1));
}

TEST(Cantilever, IncompatibleModesAreAccurateOnACoarseMeshWhileFullIntegrationLocks) {
  const double d_ref = timoshenko_tip_deflection();
  const double r8i = fe_tip_deflection(ElementType::kC3D8I, 10, 2, 2) / d_ref;
  const double r8 = fe_tip_deflection(ElementType::kC3D8, 10, 2, 2) / d_ref;
  RecordProperty("C3D8I_10x2x2_over_timoshenko", std::to_string(r8i));
  RecordProperty("C3D8_10x2x2_over_timoshenko", std::to_string(r8));
  // Beam theory ignores the clamp's restraint of the Poisson contraction and the 3D end
  // effects: the refined 3D solutions lie about 1% below it. C3D8I reproduces pure bending
  // exactly on rectangular bricks and loses another ~1.5% to the linearly varying moment on
  // this 10x2x2 mesh (measured 0.976; C3D8 0.690; C3D20 0.985).
  constexpr double kBeamTheoryTolerance = 0.03;
  EXPECT_NEAR(r8i, 1.0, kBeamTheoryTolerance) << "C3D8I 10x2x2";
  // Shear locking of the fully integrated brick with elements of aspect ratio 2:1.
  EXPECT_LT(r8, 0.85) << "C3D8 10x2x2";
  // The 20-node brick is accurate on the same coarse mesh.
  const double r20 = fe_tip_deflection(ElementType::kC3D20, 10, 2, 2) / d_ref;
  RecordProperty("C3D20_10x2x2_over_timoshenko", std::to_string(r20));
  EXPECT_NEAR(r20, 1.0, kBeamTheoryTolerance);
}

TEST(Cantilever, FullIntegrationConvergesToBeamTheoryUnderRefinement) {
  const double d_ref = timoshenko_tip_deflection();
  double previous_error = 1.0;
  for (int r : {1, 2, 4}) {
    const double ratio = fe_tip_deflection(ElementType::kC3D8, 10 * r, 2 * r, 2 * r) / d_ref;
    const double error = std::abs(ratio - 1.0);
    RecordProperty("C3D8_refinement_" + std::to_string(r), std::to_string(ratio));
    EXPECT_LT(error, previous_error) << "refinement " << r;
    EXPECT_LT(ratio, 1.0 + 0.03);  // approaches from below (stiff), up to the 3D effects
    previous_error = error;
  }
  EXPECT_LT(previous_error, 0.05);  // 40x8x8
  // C3D8I converges too and stays close at every level.
  for (int r : {1, 2}) {
    const double ratio = fe_tip_deflection(ElementType::kC3D8I, 10 * r, 2 * r, 2 * r) / d_ref;
    RecordProperty("C3D8I_refinement_" + std::to_string(r), std::to_string(ratio));
    EXPECT_NEAR(ratio, 1.0, 0.03);
  }
}

// Volumetric locking: with nu -> 1/2 the fully integrated brick must keep the volume at each of
// its 8 Gauss points and locks in bending; B-bar (C3D8B) keeps only the element's mean volume
// and behaves as at nu = 0.3, apart from the shear locking of the linear brick that refinement
// removes. Measured (tip deflection / Timoshenko): 10x2x2 C3D8B 0.754 (0.760 at nu = 0.3),
// C3D8 0.083 (0.690 at nu = 0.3); 20x4x4 C3D8B 0.906, C3D8 0.196; 40x8x8 C3D8B 0.958, C3D8 0.353.
TEST(Cantilever, BbarDoesNotLockForANearlyIncompressibleMaterial) {
  IsotropicMaterial nearly_incompressible = kSteel;
  nearly_incompressible.poisson_ratio = 0.4999;
  const double d_ref = timoshenko_tip_deflection(nearly_incompressible);
  double previous_error = 1.0;
  for (int r : {1, 2}) {
    const double bbar =
        fe_tip_deflection(ElementType::kC3D8B, 10 * r, 2 * r, 2 * r, nearly_incompressible) / d_ref;
    const double full =
        fe_tip_deflection(ElementType::kC3D8, 10 * r, 2 * r, 2 * r, nearly_incompressible) / d_ref;
    const double bbar_steel =
        fe_tip_deflection(ElementType::kC3D8B, 10 * r, 2 * r, 2 * r) / timoshenko_tip_deflection();
    RecordProperty("C3D8B_nu_0.4999_refinement_" + std::to_string(r), std::to_string(bbar));
    RecordProperty("C3D8_nu_0.4999_refinement_" + std::to_string(r), std::to_string(full));
    // Locked: a quarter of the deflection or less.
    EXPECT_LT(full, 0.25) << "C3D8 refinement " << r;
    // Not locked: as far from beam theory as at nu = 0.3 (shear locking only), within 2%.
    EXPECT_NEAR(bbar, bbar_steel, 0.02) << "C3D8B refinement " << r;
    EXPECT_LT(std::abs(bbar - 1.0), previous_error) << "C3D8B refinement " << r;
    previous_error = std::abs(bbar - 1.0);
  }
  EXPECT_LT(previous_error, 0.12);  // 20x4x4
}

}  // namespace
}  // namespace stickslip
