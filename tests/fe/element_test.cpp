// Properties of single free elements of every type on distorted geometry: symmetry, the six
// rigid-body modes as the exact null space, positive definiteness otherwise, total mass rho V
// (V computed independently) and rigid translation kinetic energy.
#include "fe/element.h"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "core/errors.h"
#include "fe_test_util.h"
#include "mesh/surface_area.h"

namespace stickslip {
namespace {

using testing::distorted_element;
using testing::independent_volume;
using testing::rigid_body_modes;

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};

// Round-off of a sum of O(100) products of O(||K||) terms in double precision.
constexpr double kRoundOff = 1e-12;
// Eigenvalues below this fraction of the largest count as zero; the smallest genuine elastic
// eigenvalue of these moderately distorted elements is above 1e-4 of the largest.
constexpr double kZeroEigenvalue = 1e-9;

struct Case {
  ElementType type;
  int zero_modes;  // 6 rigid-body modes (+ the spurious modes of reduced integration)
};

class ElementProperties : public ::testing::TestWithParam<Case> {};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return element_type_name(info.param.type);
}

TEST_P(ElementProperties, StiffnessIsSymmetricWithRigidBodyNullSpace) {
  const Case c = GetParam();
  for (unsigned seed : {1u, 2u, 3u}) {
    // Corners moved by up to 20% of the element size, mid-edge nodes by up to 5% (curved edges).
    const Eigen::Matrix3Xd X = distorted_element(c.type, seed, 0.2, 0.05);
    Eigen::MatrixXd K;
    element_stiffness(c.type, X, kSteel, K);
    ASSERT_EQ(K.rows(), 3 * nodes_per_element(c.type));
    const double norm = K.norm();
    EXPECT_LT((K - K.transpose()).norm(), kRoundOff * norm);
    const Eigen::MatrixXd R = rigid_body_modes(X);
    for (int k = 0; k < 6; ++k) {
      EXPECT_LT((K * R.col(k)).norm(), kRoundOff * norm * R.col(k).norm()) << "mode " << k;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
    const Eigen::VectorXd lam = eig.eigenvalues();
    const double lmax = lam.maxCoeff();
    int zeros = 0;
    for (int i = 0; i < lam.size(); ++i) {
      if (std::abs(lam(i)) < kZeroEigenvalue * lmax) {
        ++zeros;
      } else {
        EXPECT_GT(lam(i), 0.0);
      }
    }
    EXPECT_EQ(zeros, c.zero_modes) << "seed " << seed;
  }
}

TEST_P(ElementProperties, ConsistentMassGivesRhoVAndRigidKineticEnergy) {
  const Case c = GetParam();
  for (unsigned seed : {4u, 5u}) {
    // Straight edges: the independent volume formula needs them.
    const Eigen::Matrix3Xd X = distorted_element(c.type, seed, 0.2, 0.0);
    const double V = independent_volume(c.type, X);
    ASSERT_GT(V, 0.0);
    EXPECT_NEAR(element_volume(c.type, X), V, kRoundOff * V);
    for (MassIntegration rule : {MassIntegration::kExact, MassIntegration::kStiffnessRule}) {
      Eigen::MatrixXd M;
      element_mass(c.type, X, kSteel.density, M, rule);
      EXPECT_LT((M - M.transpose()).norm(), kRoundOff * M.norm());
      const Eigen::MatrixXd R = rigid_body_modes(X);
      // 1^T M_dir 1 = rho V for each direction, no coupling between directions.
      const Eigen::MatrixXd Mt = R.leftCols(3).transpose() * M * R.leftCols(3);
      EXPECT_LT((Mt - kSteel.density * V * Eigen::Matrix3d::Identity()).norm(),
                kRoundOff * kSteel.density * V);
      // Kinetic energy of a rigid translation with velocity v: T = rho V |v|^2 / 2.
      const Eigen::Vector3d v(0.3, -1.2, 2.0);
      const Eigen::VectorXd vel = R.leftCols(3) * v;
      EXPECT_NEAR(0.5 * vel.dot(M * vel), 0.5 * kSteel.density * V * v.squaredNorm(),
                  kRoundOff * kSteel.density * V * v.squaredNorm());
      if (rule == MassIntegration::kExact) {
        // The exact consistent mass is positive definite.
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
        EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
      }
    }
  }
}

// C3D6 with CalculiX's two-point rule (both points on the triangle's centroid) has one spurious
// zero-energy mode on a single free element besides the 6 rigid ones; a mesh constrains it (the
// patch test, and CalculiX's frequencies of wedge meshes, tests/validation, have none).
// Reduced integration of the 20-node brick (8 points x 6 strains = 48 constraints on 60 DOFs)
// leaves 6 spurious zero-energy modes on a single free element besides the 6 rigid ones; they
// are non-communicable and disappear in a mesh (checked by the patch and cantilever tests).
INSTANTIATE_TEST_SUITE_P(
    AllTypes, ElementProperties,
    ::testing::Values(Case{ElementType::kC3D8, 6}, Case{ElementType::kC3D8I, 6},
                      Case{ElementType::kC3D20, 6}, Case{ElementType::kC3D20R, 12},
                      Case{ElementType::kC3D4, 6}, Case{ElementType::kC3D10, 6},
                      Case{ElementType::kC3D8B, 6}, Case{ElementType::kC3D6, 7},
                      Case{ElementType::kC3D15, 6}, Case{ElementType::kC3D5, 6},
                      Case{ElementType::kC3D13, 6}, Case{ElementType::kC3D8R, 6}),
    case_name);

// C3D5 is by definition the 8-node brick with nodes 5-8 collapsed onto the apex: its stiffness
// and its mass with the stiffness rule equal Pᵀ K_C3D8 P and Pᵀ M_C3D8 P, P the 24 x 15 map that
// gives nodes 5-8 of the brick the apex's displacement, on distorted pyramids.
TEST(ElementKernels, PyramidIsTheCollapsedBrick) {
  for (unsigned seed : {7u, 8u, 9u}) {
    const Eigen::Matrix3Xd X = distorted_element(ElementType::kC3D5, seed, 0.2, 0.0);
    Eigen::Matrix3Xd X8(3, 8);
    X8.leftCols(5) = X;
    for (int a = 5; a < 8; ++a) X8.col(a) = X.col(4);
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(24, 15);
    for (int a = 0; a < 8; ++a) P.block<3, 3>(3 * a, 3 * std::min(a, 4)).setIdentity();
    Eigen::MatrixXd K5, K8, M5, M8;
    element_stiffness(ElementType::kC3D5, X, kSteel, K5);
    element_stiffness(ElementType::kC3D8, X8, kSteel, K8);
    EXPECT_LT((K5 - P.transpose() * K8 * P).norm(), kRoundOff * K5.norm()) << "seed " << seed;
    element_mass(ElementType::kC3D5, X, kSteel.density, M5, MassIntegration::kStiffnessRule);
    element_mass(ElementType::kC3D8, X8, kSteel.density, M8, MassIntegration::kStiffnessRule);
    EXPECT_LT((M5 - P.transpose() * M8 * P).norm(), kRoundOff * M5.norm()) << "seed " << seed;
  }
}

// C3D13 is by definition the 20-node brick with nodes 5-8 and 13-16 collapsed onto the apex:
// K and M (both rules) equal Pᵀ K_C3D20 P and Pᵀ M_C3D20 P, P the 60 x 39 map that gives the
// brick's nodes the displacements of the pyramid's nodes they stand for, on distorted pyramids
// with curved edges.
TEST(ElementKernels, QuadraticPyramidIsTheCollapsedQuadraticBrick) {
  // Brick node -> pyramid node: 0-3 base corners, 4-7 and 12-15 the apex, 8-11 base mid-edge
  // nodes (pyramid 5-8), 16-19 lateral mid-edge nodes (pyramid 9-12).
  constexpr int kOf[20] = {0, 1, 2, 3, 4, 4, 4, 4, 5, 6, 7, 8, 4, 4, 4, 4, 9, 10, 11, 12};
  for (unsigned seed : {7u, 8u, 9u}) {
    const Eigen::Matrix3Xd X = distorted_element(ElementType::kC3D13, seed, 0.2, 0.05);
    Eigen::Matrix3Xd X20(3, 20);
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(60, 39);
    for (int a = 0; a < 20; ++a) {
      X20.col(a) = X.col(kOf[a]);
      P.block<3, 3>(3 * a, 3 * kOf[a]).setIdentity();
    }
    Eigen::MatrixXd K13, K20, M13, M20;
    element_stiffness(ElementType::kC3D13, X, kSteel, K13);
    element_stiffness(ElementType::kC3D20, X20, kSteel, K20);
    EXPECT_LT((K13 - P.transpose() * K20 * P).norm(), kRoundOff * K13.norm()) << "seed " << seed;
    element_mass(ElementType::kC3D13, X, kSteel.density, M13, MassIntegration::kStiffnessRule);
    element_mass(ElementType::kC3D20, X20, kSteel.density, M20, MassIntegration::kStiffnessRule);
    EXPECT_LT((M13 - P.transpose() * M20 * P).norm(), kRoundOff * M13.norm()) << "seed " << seed;
  }
}

// Which quadratic fields C3D13 reproduces: on a right pyramid (base [-a, a]² at z = 0, apex
// (0, 0, h)) the collapsed map is x = aξ(1 − ζ)/2, y = aη(1 − ζ)/2, z = h(1 + ζ)/2, so z², xz,
// yz and xy are polynomials of the 20-node brick's space (ξηζ² is one of its 20 monomials)
// constant on the collapsed face (exact), while x² and y² need ξ²ζ² and η²ζ² (not in it). The
// interpolant Σ N_a f(x_a) equals f inside the element for the first kind (and for linear
// fields) and not for the second.
TEST(ElementKernels, QuadraticPyramidReproducesTheQuadraticFieldsOfItsCollapsedBrick) {
  const double a = 0.3, h = 0.5;
  Eigen::Matrix3Xd X = natural_node_coordinates(ElementType::kC3D13);
  for (int n = 0; n < X.cols(); ++n) {
    const Eigen::Vector3d p = X.col(n);
    X.col(n) = n == 4 ? Eigen::Vector3d(0, 0, h)
                      : Eigen::Vector3d(a * p(0) * (1 - p(2)) / 2, a * p(1) * (1 - p(2)) / 2,
                                        h * (1 + p(2)) / 2);
  }
  using Field = double (*)(const Eigen::Vector3d&);
  const Field exact[] = {[](const Eigen::Vector3d& x) { return 1.0 + x(0) - 2 * x(1) + 3 * x(2); },
                         [](const Eigen::Vector3d& x) { return x(2) * x(2); },
                         [](const Eigen::Vector3d& x) { return x(0) * x(2); },
                         [](const Eigen::Vector3d& x) { return x(1) * x(2); },
                         [](const Eigen::Vector3d& x) { return x(0) * x(1); }};
  const Field inexact[] = {[](const Eigen::Vector3d& x) { return x(0) * x(0); },
                           [](const Eigen::Vector3d& x) { return x(1) * x(1); }};
  const auto worst_error = [&](Field f) {
    Eigen::VectorXd nodal(13);
    for (int n = 0; n < 13; ++n) nodal(n) = f(X.col(n));
    double worst = 0.0;
    for (const Eigen::Vector3d& xi :
         {Eigen::Vector3d(0.3, -0.2, -0.5), Eigen::Vector3d(-0.7, 0.6, 0.1),
          Eigen::Vector3d(0.5, 0.5, 0.6)}) {
      Eigen::VectorXd N;
      Eigen::Matrix3Xd dN;
      shape_functions(ElementType::kC3D13, xi, N, dN);
      worst = std::max(worst, std::abs(N.dot(nodal) - f(X * N)));
    }
    return worst;
  };
  const double scale = a * a;  // the fields' size
  for (Field f : exact) EXPECT_LT(worst_error(f), kRoundOff * scale);
  for (Field f : inexact) EXPECT_GT(worst_error(f), 1e-3 * scale);
}

// C3D8R on a box a x b x c, built here from the closed forms: the uniform gradients of node n
// (natural corner (ξ_n, η_n, ζ_n)) are b̄ = (ξ_n / 4a, η_n / 4b, ζ_n / 4c), the one-point part is
// V B̄ᵀ D B̄, and CalculiX's hourglass stiffness is c Σ_k h_k h_kᵀ on each direction with the
// base vectors h = ηζ, ξζ, ξη, ξηζ (orthogonal to linear fields on a box) and
// c = 0.0005 E Σ (∂V/∂x)² / V = 0.0005 E (b²c² + c²a² + a²b²) / (2abc) (∂V/∂x_n = ξ_n bc / 4).
// CalculiX's one-point mass is ρV/64 for every pair of nodes.
TEST(ElementKernels, ReducedBrickOnABoxIsOnePointPlusCalculixHourglassStiffness) {
  const double a = 0.3, b = 0.5, c = 0.2, V = a * b * c;
  const Eigen::Matrix3Xd ref = natural_node_coordinates(ElementType::kC3D8R);
  Eigen::Matrix3Xd X(3, 8);
  for (int n = 0; n < 8; ++n) {
    X.col(n) =
        Eigen::Vector3d(a * (ref(0, n) + 1) / 2, b * (ref(1, n) + 1) / 2, c * (ref(2, n) + 1) / 2);
  }
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 24);
  Eigen::MatrixXd H(8, 4);
  for (int n = 0; n < 8; ++n) {
    const double gx = ref(0, n) / (4 * a), gy = ref(1, n) / (4 * b), gz = ref(2, n) / (4 * c);
    B(0, 3 * n) = gx;
    B(1, 3 * n + 1) = gy;
    B(2, 3 * n + 2) = gz;
    B(3, 3 * n) = gy;
    B(3, 3 * n + 1) = gx;
    B(4, 3 * n) = gz;
    B(4, 3 * n + 2) = gx;
    B(5, 3 * n + 1) = gz;
    B(5, 3 * n + 2) = gy;
    H.row(n) << ref(1, n) * ref(2, n), ref(0, n) * ref(2, n), ref(0, n) * ref(1, n),
        ref(0, n) * ref(1, n) * ref(2, n);
  }
  const double hg = 0.0005 * kSteel.youngs_modulus *
                    (b * b * c * c + c * c * a * a + a * a * b * b) / (2 * a * b * c);
  Eigen::MatrixXd Kref = V * B.transpose() * elasticity_matrix(kSteel) * B;
  const Eigen::MatrixXd h = hg * H * H.transpose();
  for (int m = 0; m < 8; ++m) {
    for (int n = 0; n < 8; ++n) {
      for (int d = 0; d < 3; ++d) Kref(3 * m + d, 3 * n + d) += h(m, n);
    }
  }
  Eigen::MatrixXd K, M;
  element_stiffness(ElementType::kC3D8R, X, kSteel, K);
  EXPECT_LT((K - Kref).norm(), kRoundOff * Kref.norm());
  element_mass(ElementType::kC3D8R, X, kSteel.density, M, MassIntegration::kStiffnessRule);
  for (int m = 0; m < 8; ++m) {
    for (int n = 0; n < 8; ++n) {
      EXPECT_NEAR(M(3 * m + 1, 3 * n + 1), kSteel.density * V / 64, kRoundOff * kSteel.density * V);
      EXPECT_EQ(M(3 * m, 3 * n + 2), 0.0);
    }
  }
}

// The faces of the new types as contact surfaces see them (mesh/surface_area.h): on a box of
// pyramids (bases on the box faces) and of C3D8R bricks, the faces within the x = 0 plane are
// the bases (8 nodes for C3D13: corners and base mid-edge nodes) and cover it: Σ area = ly lz.
TEST(ElementFaces, PyramidAndReducedBrickFacesCoverABoxSide) {
  const Eigen::Vector3d size(0.4, 0.3, 0.2);
  for (ElementType type : {ElementType::kC3D5, ElementType::kC3D13, ElementType::kC3D8R}) {
    const Mesh mesh = testing::box_mesh(type, 2, 2, 2, size);
    std::vector<int> side;
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (std::abs(mesh.coordinates(0, n)) < 1e-12) side.push_back(n);
    }
    const std::vector<ElementFace> faces = faces_within(mesh, side);
    ASSERT_EQ(faces.size(), 4u) << element_type_name(type);
    double area = 0.0;
    for (const ElementFace& f : faces) {
      EXPECT_EQ(f.nodes.size(), type == ElementType::kC3D13 ? 8u : 4u) << element_type_name(type);
      area += face_area(mesh, f);
    }
    EXPECT_NEAR(area, size(1) * size(2), kRoundOff * size(1) * size(2)) << element_type_name(type);
  }
}

// Exact closed forms on undistorted elements.
TEST(ElementKernels, Tet4MatchesClosedFormConstantStrainTetrahedron) {
  // K = V B^T D B with constant B from the barycentric gradients (independent construction).
  Eigen::Matrix3Xd X(3, 4);
  X << 0.1, 1.3, 0.2, 0.3, 0.0, 0.1, 0.9, 0.2, 0.05, 0.0, 0.1, 1.1;
  Eigen::Matrix4d A;
  A.row(0).setOnes();
  A.bottomRows<3>() = X;
  const Eigen::Matrix4d Ainv = A.inverse();  // L = Ainv [1; x]
  const double V = A.determinant() / 6.0;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 12);
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector3d g = Ainv.block<1, 3>(a, 1).transpose();
    B(0, 3 * a) = g(0);
    B(1, 3 * a + 1) = g(1);
    B(2, 3 * a + 2) = g(2);
    B(3, 3 * a) = g(1);
    B(3, 3 * a + 1) = g(0);
    B(4, 3 * a) = g(2);
    B(4, 3 * a + 2) = g(0);
    B(5, 3 * a + 1) = g(2);
    B(5, 3 * a + 2) = g(1);
  }
  const Eigen::MatrixXd Kref = V * B.transpose() * elasticity_matrix(kSteel) * B;
  Eigen::MatrixXd K;
  element_stiffness(ElementType::kC3D4, X, kSteel, K);
  EXPECT_LT((K - Kref).norm(), kRoundOff * Kref.norm());
  // Consistent tet4 mass: rho V / 20 (1 + delta_ab) per direction.
  Eigen::MatrixXd M;
  element_mass(ElementType::kC3D4, X, kSteel.density, M);
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      EXPECT_NEAR(M(3 * a + 1, 3 * b + 1), kSteel.density * V / 20.0 * (a == b ? 2.0 : 1.0),
                  kRoundOff * kSteel.density * V);
    }
  }
}

TEST(ElementKernels, Hex8MassOfBoxMatchesTensorProductClosedForm) {
  // Box a x b x c: m_ab = rho abc/27 * prod_d (2 if same coordinate else 1) / ... tensor form:
  // 1D linear mass on [0,h] is h/6 [2 1; 1 2].
  const double a = 0.3, b = 0.5, c = 0.2;
  Eigen::Matrix3Xd X = natural_node_coordinates(ElementType::kC3D8);
  const Eigen::Matrix3Xd ref = X;
  for (int n = 0; n < 8; ++n) X.col(n) = 0.5 * (ref.col(n) + Eigen::Vector3d::Ones());
  X.row(0) *= a;
  X.row(1) *= b;
  X.row(2) *= c;
  Eigen::MatrixXd M;
  element_mass(ElementType::kC3D8, X, kSteel.density, M);
  for (int p = 0; p < 8; ++p) {
    for (int q = 0; q < 8; ++q) {
      double m = kSteel.density;
      const double h[3] = {a, b, c};
      for (int d = 0; d < 3; ++d) m *= h[d] / 6.0 * (ref(d, p) == ref(d, q) ? 2.0 : 1.0);
      EXPECT_NEAR(M(3 * p + 2, 3 * q + 2), m, kRoundOff * kSteel.density * a * b * c);
      EXPECT_EQ(M(3 * p, 3 * q + 1), 0.0);
    }
  }
}

TEST(ElementKernels, InvertedElementThrows) {
  Eigen::Matrix3Xd X = distorted_element(ElementType::kC3D8, 7, 0.0, 0.0);
  X.col(0).swap(X.col(1));
  X.col(2).swap(X.col(3));
  X.col(4).swap(X.col(5));
  X.col(6).swap(X.col(7));
  Eigen::MatrixXd K;
  EXPECT_THROW(element_stiffness(ElementType::kC3D8, X, kSteel, K), InvalidInput);
  EXPECT_THROW(element_stiffness(ElementType::kC3D4, Eigen::Matrix3Xd::Zero(3, 5), kSteel, K),
               InvalidInput);
}

// Shape functions: partition of unity, Kronecker property at the nodes, derivatives against
// central finite differences.
TEST(ElementKernels, ShapeFunctionsInterpolateAndDerivativesMatchFiniteDifferences) {
  constexpr double kH = 1e-6;
  constexpr double kFdTolerance = 1e-8;  // O(h^2) truncation + O(eps/h) round-off
  for (ElementType t :
       {ElementType::kC3D8, ElementType::kC3D20, ElementType::kC3D4, ElementType::kC3D10,
        ElementType::kC3D6, ElementType::kC3D15, ElementType::kC3D5, ElementType::kC3D13}) {
    const Eigen::Matrix3Xd P = natural_node_coordinates(t);
    Eigen::VectorXd N, Np, Nm;
    Eigen::Matrix3Xd dN, tmp;
    for (int a = 0; a < P.cols(); ++a) {
      shape_functions(t, P.col(a), N, dN);
      for (int b = 0; b < P.cols(); ++b) EXPECT_NEAR(N(b), a == b ? 1.0 : 0.0, 1e-15);
    }
    const Eigen::Vector3d xi(0.13, 0.21, 0.17);
    shape_functions(t, xi, N, dN);
    EXPECT_NEAR(N.sum(), 1.0, 1e-15);
    for (int i = 0; i < 3; ++i) {
      shape_functions(t, xi + kH * Eigen::Vector3d::Unit(i), Np, tmp);
      shape_functions(t, xi - kH * Eigen::Vector3d::Unit(i), Nm, tmp);
      EXPECT_LT(((Np - Nm) / (2 * kH) - dN.row(i).transpose()).norm(), kFdTolerance)
          << element_type_name(t) << " d/dxi_" << i;
    }
  }
}

// Issue 22 item 6: the C3D20R mass of one box element a x b x c against the mass integrated in
// this test from the 20-node serendipity shape functions written here (C3D20 node order): with a
// 4-point Gauss rule per direction (exact: N_a N_b has degree 4 per direction) for
// MassIntegration::kExact (ANSYS SOLID186), with 2 points (CalculiX's stiffness rule) for
// kStiffnessRule; the two differ by far more than round-off.
TEST(C3D20RMass, ExactAndCalculixRulesEqualTheHandIntegratedMassOfABoxElement) {
  const double a = 0.02, b = 0.03, c = 0.05;  // m
  const int corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                            {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int mid[12][3] = {{0, -1, -1}, {1, 0, -1}, {0, 1, -1}, {-1, 0, -1},
                          {0, -1, 1},  {1, 0, 1},  {0, 1, 1},  {-1, 0, 1},
                          {-1, -1, 0}, {1, -1, 0}, {1, 1, 0},  {-1, 1, 0}};
  std::vector<std::array<int, 3>> nat;
  for (const auto& n : corner) nat.push_back({n[0], n[1], n[2]});
  for (const auto& n : mid) nat.push_back({n[0], n[1], n[2]});
  Eigen::Matrix3Xd X(3, 20);
  for (int i = 0; i < 20; ++i)
    X.col(i) =
        Eigen::Vector3d((nat[i][0] + 1) * a / 2, (nat[i][1] + 1) * b / 2, (nat[i][2] + 1) * c / 2);
  auto shape = [&](int i, double x, double y, double z) {
    const double p = nat[i][0], q = nat[i][1], r = nat[i][2];
    if (p != 0 && q != 0 && r != 0)
      return (1 + p * x) * (1 + q * y) * (1 + r * z) * (p * x + q * y + r * z - 2) / 8;
    if (p == 0) return (1 - x * x) * (1 + q * y) * (1 + r * z) / 4;
    if (q == 0) return (1 + p * x) * (1 - y * y) * (1 + r * z) / 4;
    return (1 + p * x) * (1 + q * y) * (1 - z * z) / 4;
  };
  auto hand_mass = [&](const std::vector<double>& points, const std::vector<double>& weights) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(60, 60);
    const double det_j = a * b * c / 8;
    for (size_t i = 0; i < points.size(); ++i)
      for (size_t j = 0; j < points.size(); ++j)
        for (size_t k = 0; k < points.size(); ++k) {
          const double w = weights[i] * weights[j] * weights[k] * det_j * kSteel.density;
          for (int p = 0; p < 20; ++p)
            for (int q = 0; q < 20; ++q) {
              const double m = w * shape(p, points[i], points[j], points[k]) *
                               shape(q, points[i], points[j], points[k]);
              for (int d = 0; d < 3; ++d) M(3 * p + d, 3 * q + d) += m;
            }
        }
    return M;
  };
  const double g2 = 1 / std::sqrt(3.0);
  const double s4a = std::sqrt(3.0 / 7 - 2.0 / 7 * std::sqrt(6.0 / 5));
  const double s4b = std::sqrt(3.0 / 7 + 2.0 / 7 * std::sqrt(6.0 / 5));
  const double w4a = (18 + std::sqrt(30.0)) / 36, w4b = (18 - std::sqrt(30.0)) / 36;
  const Eigen::MatrixXd exact = hand_mass({-s4b, -s4a, s4a, s4b}, {w4b, w4a, w4a, w4b});
  const Eigen::MatrixXd eight = hand_mass({-g2, g2}, {1.0, 1.0});
  Eigen::MatrixXd M;
  element_mass(ElementType::kC3D20R, X, kSteel.density, M, MassIntegration::kExact);
  EXPECT_LT((M - exact).norm(), kRoundOff * exact.norm());
  element_mass(ElementType::kC3D20R, X, kSteel.density, M, MassIntegration::kStiffnessRule);
  EXPECT_LT((M - eight).norm(), kRoundOff * eight.norm());
  EXPECT_GT((exact - eight).norm(), 1e-2 * exact.norm());  // the rules differ
}

}  // namespace
}  // namespace stickslip
