// Stress recovery: exact constant stress for linear fields on distorted meshes (integration
// points, extrapolated and averaged nodal values, complex amplitudes), extrapolation exact for
// its polynomial basis, C3D8I's pure-bending stress including the incompatible modes, and the
// sparse NodalStressOperator against the element-by-element nodal_stress.
#include "fe/stress.h"

#include <complex>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/errors.h"
#include "fe/element.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

using testing::box_mesh;
using testing::perturb_nodes;

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
constexpr double kRoundOff = 1e-10;  // relative; small dense solves and sums in double

const ElementType kAllTypes[] = {ElementType::kC3D8,   ElementType::kC3D8I, ElementType::kC3D20,
                                 ElementType::kC3D20R, ElementType::kC3D4,  ElementType::kC3D10,
                                 ElementType::kC3D6,   ElementType::kC3D15, ElementType::kC3D5,
                                 ElementType::kC3D13,  ElementType::kC3D8R};

TEST(Stress, ExtrapolationIsExactForItsPolynomialBasis) {
  for (ElementType type : kAllTypes) {
    const Eigen::MatrixXd E = stress_extrapolation_matrix(type);
    const Eigen::Matrix3Xd P = integration_points(type);
    const Eigen::Matrix3Xd Xn = natural_node_coordinates(type);
    ASSERT_EQ(E.rows(), nodes_per_element(type));
    ASSERT_EQ(E.cols(), P.cols());
    // A field that every basis contains: 1 (1 point), linear (tetrahedra), multilinear
    // (2x2x2, contains the linear one), triquadratic (3x3x3).
    const bool wedge = type == ElementType::kC3D6 || type == ElementType::kC3D15;
    auto f = [&](const Eigen::Vector3d& p) {
      if (wedge) {  // linear in the triangle (3 points) or constant (1), times the zeta basis
        const double t = P.cols() == 2 ? 1.0 : 2.5 + p(0) - 3 * p(1);
        return P.cols() == 2 ? 2.5 - 0.7 * p(2) : t * (1.0 + 0.4 * p(2) - 0.3 * p(2) * p(2));
      }
      switch (P.cols()) {
        case 1:
          return 2.5;
        case 4:
          return 2.5 + p(0) - 3 * p(1) + 0.5 * p(2);
        case 8:
          return 2.5 + p(0) - 3 * p(1) + 0.5 * p(2) + 0.7 * p(0) * p(1) * p(2);
        default:
          return 2.5 + p(0) * p(0) * p(1) - p(2) * p(2) * p(0) * p(1) * p(1);
      }
    };
    Eigen::VectorXd fg(P.cols()), fn(Xn.cols());
    for (int g = 0; g < P.cols(); ++g) fg(g) = f(P.col(g));
    for (int a = 0; a < Xn.cols(); ++a) fn(a) = f(Xn.col(a));
    EXPECT_LT((E * fg - fn).norm(), 1e-12 * fn.norm()) << element_type_name(type);
  }
}

TEST(Stress, LinearFieldGivesExactConstantNodalStressRealAndComplex) {
  const Eigen::Vector3d size(1.0, 0.8, 0.6);
  Eigen::Matrix3d A;
  A << 1, 2, -1, 0.5, -2, 1, 3, 0.2, 1;
  A *= 1e-4;
  const Eigen::Matrix3d e = 0.5 * (A + A.transpose());
  Eigen::Matrix<double, 6, 1> eps;
  eps << e(0, 0), e(1, 1), e(2, 2), 2 * e(0, 1), 2 * e(0, 2), 2 * e(1, 2);
  const Eigen::Matrix<double, 6, 1> sigma = elasticity_matrix(kSteel) * eps;
  const std::complex<double> amp(0.3, -1.7);
  for (ElementType type : kAllTypes) {
    Mesh mesh = box_mesh(type, 2, 2, 2, size);
    perturb_nodes(mesh, size, 0.08, 31, true);
    Eigen::VectorXd u(mesh.num_dofs());
    for (int n = 0; n < mesh.num_nodes(); ++n) u.segment<3>(3 * n) = A * mesh.coordinates.col(n);
    const StressMatrix S = nodal_stress(mesh, kSteel, {}, u);
    const ComplexStressMatrix Sc = nodal_stress(mesh, kSteel, {}, Eigen::VectorXcd(amp * u));
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      EXPECT_LT((S.col(n) - sigma).norm(), kRoundOff * sigma.norm()) << element_type_name(type);
      EXPECT_LT((Sc.col(n) - amp * sigma).norm(), kRoundOff * std::abs(amp) * sigma.norm());
    }
  }
}

// The strain operators used for stresses are those of the stiffness: K_e = sum_g w_g det J_g
// B_g^T D B_g for every type but C3D8R (for C3D8I with B_g = B_u + B_a T this equals the
// condensed K_uu - K_ua K_aa^-1 K_au), so the internal forces of the recovered stresses balance
// K_e u_e.
TEST(Stress, StrainOperatorsReproduceTheElementStiffness) {
  for (ElementType type : kAllTypes) {
    // C3D8R adds a hourglass stiffness that carries no strain (element_test checks its K).
    if (type == ElementType::kC3D8R) continue;
    const Eigen::Matrix3Xd X = testing::distorted_element(type, 51, 0.2, 0.0);
    std::vector<Eigen::MatrixXd> B;
    element_strain_operators(type, X, kSteel, B);
    const Eigen::Matrix3Xd P = integration_points(type);
    const Eigen::VectorXd w = integration_weights(type);
    ASSERT_EQ(B.size(), static_cast<size_t>(P.cols()));
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * X.cols(), 3 * X.cols()), Ke;
    Eigen::VectorXd N;
    Eigen::Matrix3Xd dN;
    for (int g = 0; g < P.cols(); ++g) {
      shape_functions(type, P.col(g), N, dN);
      const double det = (dN * X.transpose()).determinant();
      K += w(g) * det * B[g].transpose() * elasticity_matrix(kSteel) * B[g];
    }
    element_stiffness(type, X, kSteel, Ke);
    EXPECT_LT((K - Ke).norm(), kRoundOff * Ke.norm()) << element_type_name(type);
  }
}

// Pure bending about z of a rectangular brick: u_x = -k x y, u_y = k/2 (x^2 + nu (y^2 - z^2)),
// u_z = nu k y z gives s_xx = -E k y and all other stresses zero (closed form). The field lies in
// the span of C3D8I's compatible and incompatible modes, so with the nodal values imposed the
// condensed internal DOFs recover it exactly: the stress at the integration points is exact only
// if the incompatible-mode strains are included. C3D8 shows the parasitic shear instead.
TEST(Stress, C3D8IRecoversPureBendingStressThroughItsIncompatibleModes) {
  const double a = 0.5, b = 0.1, c = 0.08, k = 1e-3, nu = kSteel.poisson_ratio;
  Eigen::Matrix3Xd X = natural_node_coordinates(ElementType::kC3D8);
  X.row(0) *= a;
  X.row(1) *= b;
  X.row(2) *= c;
  Eigen::VectorXd ue(24);
  for (int n = 0; n < 8; ++n) {
    const double x = X(0, n), y = X(1, n), z = X(2, n);
    ue.segment<3>(3 * n) << -k * x * y, 0.5 * k * (x * x + nu * (y * y - z * z)), nu * k * y * z;
  }
  const StressMatrix S = element_stress_at_integration_points(ElementType::kC3D8I, X, kSteel, ue);
  const Eigen::Matrix3Xd P = integration_points(ElementType::kC3D8I);
  const double scale = kSteel.youngs_modulus * k * b;
  for (int g = 0; g < 8; ++g) {
    Eigen::Matrix<double, 6, 1> exact = Eigen::Matrix<double, 6, 1>::Zero();
    exact(0) = -kSteel.youngs_modulus * k * (b * P(1, g));
    EXPECT_LT((S.col(g) - exact).norm(), kRoundOff * scale) << "point " << g;
  }
  const StressMatrix S8 = element_stress_at_integration_points(ElementType::kC3D8, X, kSteel, ue);
  EXPECT_GT(S8.row(3).cwiseAbs().maxCoeff(), 0.1 * scale);  // parasitic shear s_xy
}

// The assembled operator G must reproduce nodal_stress (element by element, the reference) for
// every element type, on a distorted mesh, for all elements and for a subset (averaging over the
// listed elements only), real and complex, with one and two threads.
TEST(Stress, NodalStressOperatorMatchesElementByElementStress) {
  const Eigen::Vector3d size(1.0, 0.8, 0.6);
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> uniform(-1e-4, 1e-4);
  for (ElementType type : kAllTypes) {
    Mesh mesh = box_mesh(type, 3, 2, 2, size);
    perturb_nodes(mesh, size, 0.08, 17, true);
    Eigen::MatrixXcd x(mesh.num_dofs(), 2);
    for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = {uniform(rng), uniform(rng)};
    std::vector<int> subset;
    for (int e = 0; e < mesh.num_elements(); e += 2) subset.push_back(e);
    for (const bool all : {true, false}) {
      const std::span<const int> elements = all ? std::span<const int>{} : std::span(subset);
      const NodalStressOperator G(mesh, kSteel, {}, elements);
      ASSERT_EQ(G.num_nodes(), mesh.num_nodes());
      for (const int threads : {1, 2}) {
        const std::vector<ComplexStressMatrix> S = G.apply(x, threads);
        ASSERT_EQ(S.size(), 2u);
        for (int j = 0; j < 2; ++j) {
          const ComplexStressMatrix ref =
              nodal_stress(mesh, kSteel, {}, Eigen::VectorXcd(x.col(j)), elements);
          EXPECT_LT((S[j] - ref).cwiseAbs().maxCoeff(), kRoundOff * ref.cwiseAbs().maxCoeff())
              << element_type_name(type) << (all ? " all" : " subset") << " threads " << threads;
        }
      }
    }
  }
  const Mesh mesh = box_mesh(ElementType::kC3D8, 1, 1, 1, size);
  const NodalStressOperator G(mesh, kSteel, {});
  EXPECT_THROW(G.apply(Eigen::MatrixXd(Eigen::MatrixXd::Zero(mesh.num_dofs() + 1, 1))),
               InvalidInput);
  EXPECT_THROW(NodalStressOperator(mesh, kSteel, {}, std::vector<int>{1}), InvalidInput);
}

}  // namespace
}  // namespace stickslip
