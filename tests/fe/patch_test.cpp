// Patch test and uniaxial stress: linear displacement fields must be reproduced exactly (to
// round-off) by meshes of distorted elements of every type, with the exact constant stress.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/element.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

using testing::boundary_nodes;
using testing::box_mesh;
using testing::element_coordinates;
using testing::perturb_nodes;

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
// Round-off of a sparse direct solve with condition number ~1e4-1e5 for these small patches.
constexpr double kPatchTolerance = 1e-9;

Eigen::Matrix<double, 6, 1> voigt_strain(const Eigen::Matrix3d& grad) {
  const Eigen::Matrix3d e = 0.5 * (grad + grad.transpose());
  Eigen::Matrix<double, 6, 1> v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(0, 1), 2 * e(0, 2), 2 * e(1, 2);
  return v;
}

// Solves K u = 0 with u prescribed on the constrained DOFs: u_f = -K_ff^-1 K_fc u_c.
Eigen::VectorXd solve_prescribed(const SparseMatrix& K, const DofMap& map,
                                 const Eigen::VectorXd& u_prescribed) {
  Eigen::VectorXd uc = u_prescribed;
  for (int f = 0; f < map.num_free(); ++f) uc(map.full_dof(f)) = 0.0;
  const Eigen::VectorXd rhs = map.restrict(Eigen::VectorXd(-(K * uc)));
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(map.restrict(K));
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd uf = ldlt.solve(rhs);
  return uc + map.expand(uf);
}

class PatchTest : public ::testing::TestWithParam<ElementType> {};

TEST_P(PatchTest, DistortedMeshReproducesLinearFieldAndConstantStress) {
  const ElementType type = GetParam();
  const Eigen::Vector3d size(1.0, 0.8, 0.6);
  const int n = nodes_per_element(type) == 4 || nodes_per_element(type) == 10 ? 2 : 3;
  Mesh mesh = box_mesh(type, n, n, n, size);
  // Interior nodes moved by up to 35% of the cell size: strongly non-rectangular elements.
  // (Pyramids: 15%, their apex is at half a cell from their base.)
  const bool pyramid = type == ElementType::kC3D5 || type == ElementType::kC3D13;
  const double distortion = pyramid ? 0.15 : 0.35;
  perturb_nodes(mesh, size, distortion * size.minCoeff() / n, 21, true);
  SparseMatrix K;
  assemble_stiffness_mass(mesh, kSteel, {}, &K, nullptr);

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> g(-1e-3, 1e-3);
  Eigen::Matrix3d A;
  for (int i = 0; i < 9; ++i) A(i) = g(rng);
  const Eigen::Vector3d c(g(rng), g(rng), g(rng));
  Eigen::VectorXd u_exact(mesh.num_dofs());
  for (int k = 0; k < mesh.num_nodes(); ++k) {
    u_exact.segment<3>(3 * k) = A * mesh.coordinates.col(k) + c;
  }
  const std::vector<int> boundary = boundary_nodes(mesh, size);
  const DofMap map = DofMap::from_nodes(mesh.num_nodes(), boundary);
  ASSERT_GT(map.num_free(), 0);
  const Eigen::VectorXd u = solve_prescribed(K, map, u_exact);
  EXPECT_LT((u - u_exact).lpNorm<Eigen::Infinity>(),
            kPatchTolerance * u_exact.lpNorm<Eigen::Infinity>());

  const Eigen::Matrix<double, 6, 1> sigma_exact = elasticity_matrix(kSteel) * voigt_strain(A);
  std::vector<Eigen::MatrixXd> B;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    element_strain_operators(type, element_coordinates(mesh, e), kSteel, B);
    const auto nodes = mesh.element_nodes(e);
    Eigen::VectorXd ue(3 * nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) ue.segment<3>(3 * a) = u.segment<3>(3 * nodes[a]);
    for (const Eigen::MatrixXd& Bg : B) {
      const Eigen::Matrix<double, 6, 1> sigma = elasticity_matrix(kSteel) * Bg * ue;
      EXPECT_LT((sigma - sigma_exact).norm(), kPatchTolerance * sigma_exact.norm());
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllTypes, PatchTest,
                         ::testing::Values(ElementType::kC3D8, ElementType::kC3D8I,
                                           ElementType::kC3D20, ElementType::kC3D20R,
                                           ElementType::kC3D4, ElementType::kC3D10,
                                           ElementType::kC3D8B, ElementType::kC3D6,
                                           ElementType::kC3D15, ElementType::kC3D5,
                                           ElementType::kC3D13, ElementType::kC3D8R),
                         [](const auto& info) { return element_type_name(info.param); });

// Independent B^T D B implementation of the Wilson incompatible-mode hexahedron, with
// (taylor = true) or without the Taylor modification, built from the public shape functions.
Eigen::MatrixXd wilson_hex8_stiffness(const Eigen::Matrix3Xd& X, bool taylor) {
  const Eigen::Matrix3Xd P = integration_points(ElementType::kC3D8);
  const Eigen::VectorXd w = integration_weights(ElementType::kC3D8);
  const Eigen::Matrix<double, 6, 6> D = elasticity_matrix(kSteel);
  Eigen::VectorXd N;
  Eigen::Matrix3Xd dN;
  shape_functions(ElementType::kC3D8, Eigen::Vector3d::Zero(), N, dN);
  const Eigen::Matrix3d J0 = dN * X.transpose();
  Eigen::MatrixXd Ke = Eigen::MatrixXd::Zero(33, 33);
  for (int g = 0; g < P.cols(); ++g) {
    shape_functions(ElementType::kC3D8, P.col(g), N, dN);
    const Eigen::Matrix3d J = dN * X.transpose();
    Eigen::Matrix3Xd G(3, 11);
    G.leftCols(8) = J.inverse() * dN;
    const Eigen::Matrix3d dP = (-2.0 * P.col(g)).asDiagonal();
    G.rightCols(3) = taylor
                         ? Eigen::Matrix3d(J0.determinant() / J.determinant() * J0.inverse() * dP)
                         : Eigen::Matrix3d(J.inverse() * dP);
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 33);
    for (int a = 0; a < 11; ++a) {
      B(0, 3 * a) = G(0, a);
      B(1, 3 * a + 1) = G(1, a);
      B(2, 3 * a + 2) = G(2, a);
      B(3, 3 * a) = G(1, a);
      B(3, 3 * a + 1) = G(0, a);
      B(4, 3 * a) = G(2, a);
      B(4, 3 * a + 2) = G(0, a);
      B(5, 3 * a + 1) = G(2, a);
      B(5, 3 * a + 2) = G(1, a);
    }
    Ke += w(g) * J.determinant() * B.transpose() * D * B;
  }
  return Ke.topLeftCorner(24, 24) - Ke.topRightCorner(24, 9) *
                                        Ke.bottomRightCorner(9, 9).inverse() *
                                        Ke.bottomLeftCorner(9, 24);
}

// The kernel's C3D8I equals the independent Taylor-modified construction; without the Taylor
// modification the same distorted patch fails the patch test, so the patch test above can see
// the difference.
TEST(PatchTest, TaylorModificationIsWhatMakesC3D8IPass) {
  const Eigen::Vector3d size(1.0, 0.8, 0.6);
  Mesh mesh = box_mesh(ElementType::kC3D8I, 2, 2, 2, size);
  perturb_nodes(mesh, size, 0.35 * 0.6 / 2, 22, true);
  const std::vector<int> boundary = boundary_nodes(mesh, size);
  const DofMap map = DofMap::from_nodes(mesh.num_nodes(), boundary);
  Eigen::Matrix3d A;
  A << 1, 2, -1, 0.5, -2, 1, 3, 0.2, 1;
  A *= 1e-4;
  Eigen::VectorXd u_exact(mesh.num_dofs());
  for (int k = 0; k < mesh.num_nodes(); ++k)
    u_exact.segment<3>(3 * k) = A * mesh.coordinates.col(k);
  double error[2];
  for (bool taylor : {true, false}) {
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(mesh.num_dofs(), mesh.num_dofs());
    Eigen::MatrixXd Kkernel;
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const Eigen::Matrix3Xd X = element_coordinates(mesh, e);
      const Eigen::MatrixXd Ke = wilson_hex8_stiffness(X, taylor);
      if (taylor) {
        element_stiffness(ElementType::kC3D8I, X, kSteel, Kkernel);
        EXPECT_LT((Ke - Kkernel).norm(), 1e-12 * Ke.norm());
      }
      const auto nodes = mesh.element_nodes(e);
      for (int a = 0; a < 8; ++a) {
        for (int b = 0; b < 8; ++b) {
          K.block<3, 3>(3 * nodes[a], 3 * nodes[b]) += Ke.block<3, 3>(3 * a, 3 * b);
        }
      }
    }
    const SparseMatrix Ks = K.sparseView();
    const Eigen::VectorXd u = solve_prescribed(Ks, map, u_exact);
    error[taylor ? 0 : 1] =
        (u - u_exact).lpNorm<Eigen::Infinity>() / u_exact.lpNorm<Eigen::Infinity>();
  }
  EXPECT_LT(error[0], kPatchTolerance);
  EXPECT_GT(error[1], 1e-4) << error[1];  // the unmodified Wilson element fails visibly
}

// Unit-cube mesh, symmetry planes x=0, y=0, z=0 held in their normal direction, face x = L
// displaced by delta: the exact solution is uniaxial stress, so the reaction on x = L divided by
// the area over delta/L gives E, and the lateral contraction gives nu (Hooke's law).
class UniaxialTest : public ::testing::TestWithParam<ElementType> {};

TEST_P(UniaxialTest, CubeReproducesYoungsModulusAndPoissonRatio) {
  const ElementType type = GetParam();
  const double L = 1.0, delta = 1e-4;
  const Eigen::Vector3d size(L, L, L);
  const Mesh mesh = box_mesh(type, 2, 2, 2, size);
  SparseMatrix K;
  assemble_stiffness_mass(mesh, kSteel, {}, &K, nullptr);
  std::vector<int> constrained;
  Eigen::VectorXd u_prescribed = Eigen::VectorXd::Zero(mesh.num_dofs());
  std::vector<int> loaded;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d x = mesh.coordinates.col(n);
    for (int d = 0; d < 3; ++d) {
      if (std::abs(x(d)) < 1e-12) constrained.push_back(dof_of(n, d));
    }
    if (std::abs(x(0) - L) < 1e-12) {
      constrained.push_back(dof_of(n, 0));
      u_prescribed(dof_of(n, 0)) = delta;
      loaded.push_back(n);
    }
  }
  const DofMap map(mesh.num_dofs(), constrained);
  const Eigen::VectorXd u = solve_prescribed(K, map, u_prescribed);
  const Eigen::VectorXd r = K * u;  // reactions at constrained DOFs
  double force = 0.0;
  for (int n : loaded) force += r(dof_of(n, 0));
  const double E = (force / (L * L)) / (delta / L);
  EXPECT_NEAR(E, kSteel.youngs_modulus, kPatchTolerance * kSteel.youngs_modulus);
  // Node at (L, L, L): u_y = -nu delta.
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if ((mesh.coordinates.col(n) - size).norm() < 1e-12) {
      EXPECT_NEAR(-u(dof_of(n, 1)) / delta, kSteel.poisson_ratio, kPatchTolerance);
      EXPECT_NEAR(-u(dof_of(n, 2)) / delta, kSteel.poisson_ratio, kPatchTolerance);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllTypes, UniaxialTest,
                         ::testing::Values(ElementType::kC3D8, ElementType::kC3D8I,
                                           ElementType::kC3D20, ElementType::kC3D20R,
                                           ElementType::kC3D4, ElementType::kC3D10,
                                           ElementType::kC3D8B, ElementType::kC3D6,
                                           ElementType::kC3D15),
                         [](const auto& info) { return element_type_name(info.param); });

}  // namespace
}  // namespace stickslip
