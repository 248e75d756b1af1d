// C3D8B (B-bar, mean dilatation) against an implementation written here from the definition
// (ANSYS Theory Reference, "B-bar method"; Hughes 1980): on a distorted brick,
//   K = Σ_g w_g det J_g B̄_gᵀ D B̄_g,  B̄_g = B_g + (1/3) m (b̄ - b_g)ᵀ,
// with the test's own trilinear shape functions, 2x2x2 Gauss rule and 6 x 24 strain operators
// (the element code instead splits K into a deviatoric and a rank-one volumetric part).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "fe/element.h"
#include "fe/material.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

// Natural coordinates of the 8 corners in CalculiX order.
constexpr double kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

// Physical gradients (3 x 8) of the trilinear shape functions at xi; returns det J.
double physical_gradients(const Eigen::Matrix3Xd& X, const Eigen::Vector3d& xi,
                          Eigen::Matrix<double, 3, 8>& G) {
  Eigen::Matrix<double, 3, 8> dN;
  for (int a = 0; a < 8; ++a) {
    const double s[3] = {1 + kCorner[a][0] * xi(0), 1 + kCorner[a][1] * xi(1),
                         1 + kCorner[a][2] * xi(2)};
    dN(0, a) = kCorner[a][0] * s[1] * s[2] / 8;
    dN(1, a) = kCorner[a][1] * s[0] * s[2] / 8;
    dN(2, a) = kCorner[a][2] * s[0] * s[1] / 8;
  }
  const Eigen::Matrix3d J = dN * X.transpose();  // J(i, j) = dx_j / dxi_i
  G = J.inverse() * dN;
  return J.determinant();
}

Eigen::Matrix<double, 6, 24> strain_matrix(const Eigen::Matrix<double, 3, 8>& G) {
  Eigen::Matrix<double, 6, 24> B = Eigen::Matrix<double, 6, 24>::Zero();
  for (int a = 0; a < 8; ++a) {
    B(0, 3 * a) = G(0, a);
    B(1, 3 * a + 1) = G(1, a);
    B(2, 3 * a + 2) = G(2, a);
    B(3, 3 * a) = G(1, a);  // gamma_xy
    B(3, 3 * a + 1) = G(0, a);
    B(4, 3 * a) = G(2, a);  // gamma_xz
    B(4, 3 * a + 2) = G(0, a);
    B(5, 3 * a + 1) = G(2, a);  // gamma_yz
    B(5, 3 * a + 2) = G(1, a);
  }
  return B;
}

TEST(Bbar, StiffnessMatchesTheDefinitionOnDistortedBricks) {
  const IsotropicMaterial material{.youngs_modulus = 7e10, .poisson_ratio = 0.45, .density = 1};
  const Eigen::Matrix<double, 6, 6> D = elasticity_matrix(material);
  const double g = 1.0 / std::sqrt(3.0);
  Eigen::Matrix<double, 6, 1> m;
  m << 1, 1, 1, 0, 0, 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    const Eigen::Matrix3Xd X = testing::distorted_element(ElementType::kC3D8B, seed, 0.2, 0.0);
    std::vector<Eigen::Matrix<double, 6, 24>> B;
    std::vector<double> dV;
    Eigen::Matrix<double, 1, 24> bbar = Eigen::Matrix<double, 1, 24>::Zero();
    double volume = 0.0;
    for (int k = 0; k < 8; ++k) {
      Eigen::Matrix<double, 3, 8> G;
      // Gauss points in element.h's order: xi fastest, then eta, then zeta.
      const Eigen::Vector3d xi(k & 1 ? g : -g, k & 2 ? g : -g, k & 4 ? g : -g);
      const double det = physical_gradients(X, xi, G);
      B.push_back(strain_matrix(G));
      dV.push_back(det);  // Gauss weights are 1
      bbar += det * m.transpose() * B.back();
      volume += det;
    }
    bbar /= volume;
    Eigen::Matrix<double, 24, 24> K_ref = Eigen::Matrix<double, 24, 24>::Zero();
    std::vector<Eigen::Matrix<double, 6, 24>> Bbar_ref;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Matrix<double, 6, 24> Bbar = B[k] + m * (bbar - m.transpose() * B[k]) / 3.0;
      Bbar_ref.push_back(Bbar);
      K_ref += dV[k] * Bbar.transpose() * D * Bbar;
    }
    Eigen::MatrixXd K;
    element_stiffness(ElementType::kC3D8B, X, material, K);
    constexpr double kRoundOff = 1e-12;  // relative, sums of a few hundred products
    EXPECT_LT((K - K_ref).norm(), kRoundOff * K_ref.norm()) << "seed " << seed;
    // The strain operators used for stresses are B̄ at the 8 Gauss points (same order).
    std::vector<Eigen::MatrixXd> Bel;
    element_strain_operators(ElementType::kC3D8B, X, material, Bel);
    ASSERT_EQ(Bel.size(), 8u);
    for (int k = 0; k < 8; ++k) {
      EXPECT_LT((Bel[k] - Bbar_ref[k]).norm(), kRoundOff * Bbar_ref[k].norm()) << "point " << k;
    }
    // Differs from full integration (C3D8) only through the volumetric part.
    Eigen::MatrixXd K8;
    element_stiffness(ElementType::kC3D8, X, material, K8);
    EXPECT_GT((K - K8).norm(), 1e-3 * K8.norm());
  }
}

// One volumetric constraint per element: as the bulk modulus grows, exactly one eigenvalue of a
// free C3D8B grows with it (the rank of κ V b̄ b̄ᵀ), against 7 for the fully integrated C3D8
// (the divergence at its 8 Gauss points, over the element's deformation modes, spans 7
// dimensions on a parallelepiped: one combination of the 8 values is never excited).
TEST(Bbar, OneVolumetricConstraintPerElement) {
  const Eigen::Matrix3Xd X = testing::distorted_element(ElementType::kC3D8, 4, 0.0, 0.0);
  auto stiff_eigenvalues = [&](ElementType type) {
    IsotropicMaterial a{.youngs_modulus = 1.0, .poisson_ratio = 0.3, .density = 1};
    IsotropicMaterial b{.youngs_modulus = 1.0, .poisson_ratio = 0.499999, .density = 1};
    // Same shear modulus: E = 2 G (1 + nu).
    b.youngs_modulus = 2.0 * shear_modulus(a) * (1.0 + b.poisson_ratio);
    Eigen::MatrixXd Ka, Kb;
    element_stiffness(type, X, a, Ka);
    element_stiffness(type, X, b, Kb);
    const Eigen::VectorXd ea = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Ka).eigenvalues();
    const Eigen::VectorXd eb = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Kb).eigenvalues();
    // Eigenvalues that grew with the bulk modulus (κ ratio ~ 1e5) by more than 100 times the
    // largest shear-governed one.
    int count = 0;
    for (int i = 0; i < eb.size(); ++i) count += eb(i) > 100.0 * ea.maxCoeff();
    return count;
  };
  EXPECT_EQ(stiff_eigenvalues(ElementType::kC3D8B), 1);
  EXPECT_EQ(stiff_eigenvalues(ElementType::kC3D8), 7);
}

}  // namespace
}  // namespace stickslip
