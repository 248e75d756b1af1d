// Assembly, Dirichlet elimination, nodal forces and node-pair springs against matrices built by
// hand from the element kernels and closed forms.
#include "fe/assembly.h"

#include <cmath>
#include <numeric>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "core/errors.h"
#include "fe/dof_map.h"
#include "fe/loads.h"
#include "fe/springs.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

using testing::box_mesh;
using testing::element_coordinates;
using testing::perturb_nodes;

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
constexpr double kRoundOff = 1e-13;  // relative; sums of a few element contributions

// Dense reference: element matrices placed by hand at DOFs 3*node + d.
void reference_matrices(const Mesh& mesh, std::span<const int> elements,
                        const AssemblyOptions& options, Eigen::MatrixXd& K, Eigen::MatrixXd& M) {
  K = Eigen::MatrixXd::Zero(mesh.num_dofs(), mesh.num_dofs());
  M = K;
  Eigen::MatrixXd Ke, Me;
  for (int e : elements) {
    const ElementType t = effective_element_type(mesh.element_types[e], options);
    const Eigen::Matrix3Xd X = element_coordinates(mesh, e);
    element_stiffness(t, X, kSteel, Ke);
    element_mass(t, X, kSteel.density, Me, options.mass_integration);
    const auto nodes = mesh.element_nodes(e);
    for (size_t a = 0; a < nodes.size(); ++a) {
      for (size_t b = 0; b < nodes.size(); ++b) {
        K.block<3, 3>(3 * nodes[a], 3 * nodes[b]) += Ke.block<3, 3>(3 * a, 3 * b);
        M.block<3, 3>(3 * nodes[a], 3 * nodes[b]) += Me.block<3, 3>(3 * a, 3 * b);
      }
    }
  }
}

void expect_both_triangles_stored(const SparseMatrix& A) {
  ASSERT_TRUE(A.isCompressed());
  for (int c = 0; c < A.outerSize(); ++c) {
    for (SparseMatrix::InnerIterator it(A, c); it; ++it) {
      // The transposed position must be stored too (binary search in column `row`).
      const int* first = A.innerIndexPtr() + A.outerIndexPtr()[it.row()];
      const int* last = A.innerIndexPtr() + A.outerIndexPtr()[it.row() + 1];
      ASSERT_TRUE(std::binary_search(first, last, c)) << it.row() << "," << c;
    }
  }
}

TEST(Assembly, EqualsElementMatricesPlacedByHand) {
  const Eigen::Vector3d size(2.0, 1.0, 0.7);
  for (ElementType type : {ElementType::kC3D8, ElementType::kC3D8I, ElementType::kC3D20,
                           ElementType::kC3D20R, ElementType::kC3D4, ElementType::kC3D10}) {
    const bool tet = nodes_per_element(type) <= 10 && nodes_per_element(type) != 8;
    Mesh mesh = box_mesh(type, tet ? 1 : 2, 1, 1, size);
    perturb_nodes(mesh, size, 0.1, 11, false);
    std::vector<int> all(mesh.num_elements());
    std::iota(all.begin(), all.end(), 0);
    const AssemblyOptions options;
    SparseMatrix K, M;
    assemble_stiffness_mass(mesh, kSteel, options, &K, &M);
    Eigen::MatrixXd Kref, Mref;
    reference_matrices(mesh, all, options, Kref, Mref);
    EXPECT_LT((Eigen::MatrixXd(K) - Kref).norm(), kRoundOff * Kref.norm())
        << element_type_name(type);
    EXPECT_LT((Eigen::MatrixXd(M) - Mref).norm(), kRoundOff * Mref.norm())
        << element_type_name(type);
    expect_both_triangles_stored(K);
    expect_both_triangles_stored(M);
    EXPECT_EQ(SparseMatrix(K - SparseMatrix(K.transpose())).norm(), 0.0);
  }
}

TEST(Assembly, Hex8FormulationOptionOverridesTheMesh) {
  const Eigen::Vector3d size(2.0, 1.0, 0.7);
  Mesh mesh = box_mesh(ElementType::kC3D8, 2, 1, 1, size);
  perturb_nodes(mesh, size, 0.1, 12, false);
  mesh.element_types[1] = ElementType::kC3D8I;  // mixed mesh
  std::vector<int> all{0, 1};
  for (auto f : {AssemblyOptions::Hex8Formulation::kAsMesh, AssemblyOptions::Hex8Formulation::kFull,
                 AssemblyOptions::Hex8Formulation::kIncompatible}) {
    AssemblyOptions options;
    options.hex8 = f;
    SparseMatrix K;
    assemble_stiffness_mass(mesh, kSteel, options, &K, nullptr);
    Eigen::MatrixXd Kref, Mref;
    reference_matrices(mesh, all, options, Kref, Mref);
    EXPECT_LT((Eigen::MatrixXd(K) - Kref).norm(), kRoundOff * Kref.norm());
  }
  // The formulations really differ (C3D8I is softer in bending).
  EXPECT_EQ(effective_element_type(ElementType::kC3D8I,
                                   {.hex8 = AssemblyOptions::Hex8Formulation::kFull}),
            ElementType::kC3D8);
}

TEST(Assembly, ElementSubsetAndThreadsGiveTheSameSums) {
  const Eigen::Vector3d size(1.2, 1.0, 1.0);
  Mesh mesh = box_mesh(ElementType::kC3D8I, 12, 10, 10, size);  // 1200 elements: threaded path
  perturb_nodes(mesh, size, 0.02, 13, false);
  AssemblyOptions serial;
  serial.num_threads = 1;
  AssemblyOptions threaded;
  threaded.num_threads = 2;
  SparseMatrix K1, M1, K2, M2;
  assemble_stiffness_mass(mesh, kSteel, serial, &K1, &M1);
  assemble_stiffness_mass(mesh, kSteel, threaded, &K2, &M2);
  // Same pattern; values equal up to the order of summation.
  EXPECT_EQ(K1.nonZeros(), K2.nonZeros());
  EXPECT_LT(SparseMatrix(K1 - K2).norm(), kRoundOff * K1.norm());
  EXPECT_LT(SparseMatrix(M1 - M2).norm(), kRoundOff * M1.norm());
  // Two "bodies": the halves of the element list add up to the whole.
  std::vector<int> a, b;
  for (int e = 0; e < mesh.num_elements(); ++e) (e % 3 == 0 ? a : b).push_back(e);
  SparseMatrix Ka, Kb;
  assemble_stiffness_mass(mesh, a, kSteel, serial, &Ka, nullptr);
  assemble_stiffness_mass(mesh, b, kSteel, serial, &Kb, nullptr);
  EXPECT_EQ(Ka.rows(), mesh.num_dofs());
  EXPECT_LT(SparseMatrix(Ka + Kb - K1).norm(), kRoundOff * K1.norm());
  // Total mass per direction from the assembled M: 1^T M_x 1 = rho V (V = box volume).
  Eigen::VectorXd ex = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (int n = 0; n < mesh.num_nodes(); ++n) ex(3 * n) = 1.0;
  const double V = size.prod();  // perturbation keeps the boundary? No: compute from elements.
  double Vsum = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    Vsum += testing::independent_volume(ElementType::kC3D8, element_coordinates(mesh, e));
  }
  EXPECT_NEAR(ex.dot(M1 * ex), kSteel.density * Vsum, 1e-12 * kSteel.density * V);
}

TEST(Assembly, BadInputThrows) {
  Mesh mesh = box_mesh(ElementType::kC3D8, 1, 1, 1, Eigen::Vector3d::Ones());
  SparseMatrix K;
  const std::vector<int> bad{0, 0};
  EXPECT_THROW(assemble_stiffness_mass(mesh, bad, kSteel, {}, &K, nullptr), InvalidInput);
  const std::vector<int> out{3};
  EXPECT_THROW(assemble_stiffness_mass(mesh, out, kSteel, {}, &K, nullptr), InvalidInput);
  AssemblyOptions negative_threads;
  negative_threads.num_threads = -1;
  EXPECT_THROW(assemble_stiffness_mass(mesh, kSteel, negative_threads, &K, nullptr), InvalidInput);
  IsotropicMaterial m = kSteel;
  m.poisson_ratio = 0.6;
  EXPECT_THROW(assemble_stiffness_mass(mesh, m, {}, &K, nullptr), InvalidInput);
  // An inverted element is reported with its id.
  mesh.coordinates.col(mesh.element_nodes(0)[6]) = Eigen::Vector3d(-3, -3, -3);
  try {
    assemble_stiffness_mass(mesh, kSteel, {}, &K, nullptr);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("element 1"), std::string::npos) << e.what();
  }
}

TEST(DofMap, RestrictExpandRoundTrip) {
  const int nn = 5;
  const std::vector<int> nodes{1, 3};
  const DofMap map = DofMap::from_nodes(nn, nodes, {true, false, true});
  EXPECT_EQ(map.num_dofs(), 15);
  EXPECT_EQ(map.num_constrained(), 4);
  EXPECT_EQ(map.num_free(), 11);
  EXPECT_EQ(map.free_index(dof_of(1, 0)), -1);
  EXPECT_EQ(map.free_index(dof_of(1, 1)), 3);  // DOFs 0,1,2 free before it
  for (int f = 0; f < map.num_free(); ++f) EXPECT_EQ(map.free_index(map.full_dof(f)), f);
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  Eigen::VectorXd xf(map.num_free());
  for (int i = 0; i < xf.size(); ++i) xf(i) = g(rng);
  const Eigen::VectorXd x = map.expand(xf);
  EXPECT_EQ(x(dof_of(3, 2)), 0.0);
  EXPECT_EQ((map.restrict(x) - xf).norm(), 0.0);
  const Eigen::VectorXcd xc = map.expand(Eigen::VectorXcd(xf.cast<std::complex<double>>()));
  EXPECT_EQ((map.restrict(xc).real() - xf).norm(), 0.0);
  // Sparse restriction equals the dense submatrix of free rows and columns.
  Eigen::MatrixXd A(15, 15);
  for (int i = 0; i < 15; ++i) {
    for (int j = 0; j < 15; ++j) A(i, j) = (i + 2 * j) % 4 == 0 ? 0.0 : i - 0.5 * j;
  }
  const SparseMatrix As = A.sparseView();
  const Eigen::MatrixXd R = Eigen::MatrixXd(map.restrict(As));
  for (int i = 0; i < map.num_free(); ++i) {
    for (int j = 0; j < map.num_free(); ++j)
      EXPECT_EQ(R(i, j), A(map.full_dof(i), map.full_dof(j)));
  }
  // x^T A x over free DOFs equals the restricted form (expand is the transpose of restrict).
  EXPECT_NEAR(x.dot(A * x), xf.dot(R * xf), 1e-12 * A.norm() * xf.squaredNorm());
  const Eigen::MatrixXd Xf = Eigen::MatrixXd::Ones(map.num_free(), 2);
  EXPECT_EQ(map.expand(Xf).sum(), 2.0 * map.num_free());
  EXPECT_THROW(DofMap(4, std::vector<int>{4}), InvalidInput);
  EXPECT_THROW(map.restrict(Eigen::VectorXd(3)), InvalidInput);
}

TEST(NodalForces, SumIntoTheGlobalVector) {
  const std::vector<NodalForce> f{{1, {1, 2, 3}}, {0, {0, 0, -1}}, {1, {0.5, 0, 0}}};
  const Eigen::VectorXd v = nodal_force_vector(3, f);
  ASSERT_EQ(v.size(), 9);
  EXPECT_EQ(v(dof_of(1, 0)), 1.5);
  EXPECT_EQ(v(dof_of(1, 1)), 2.0);
  EXPECT_EQ(v(dof_of(1, 2)), 3.0);
  EXPECT_EQ(v(dof_of(0, 2)), -1.0);
  EXPECT_EQ(v.segment<3>(6).norm(), 0.0);
  const std::vector<NodalForce> bad{{3, {1, 0, 0}}};
  EXPECT_THROW(nodal_force_vector(3, bad), InvalidInput);
}

Eigen::Matrix3d rotated_frame() {
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  return Q.transpose();  // rows t1, t2, n = columns of Q
}

TEST(Springs, RotatedFrameStiffnessAndSignConvention) {
  const Eigen::Matrix3d R = rotated_frame();
  const Eigen::Vector3d t1 = R.row(0), t2 = R.row(1), n = R.row(2);
  const NodePairSpring s{
      .node_a = 0, .node_b = 2, .frame = R, .k_t1 = 3e9, .k_t2 = 5e9, .k_n = 7e9};
  // Analytic: S = kt1 t1 t1^T + kt2 t2 t2^T + kn n n^T; K = [S -S; -S S].
  const Eigen::Matrix3d S =
      3e9 * t1 * t1.transpose() + 5e9 * t2 * t2.transpose() + 7e9 * n * n.transpose();
  const Eigen::Matrix<double, 6, 6> K6 = spring_stiffness(s);
  EXPECT_LT((K6.topLeftCorner<3, 3>() - S).norm(), 1e-15 * S.norm());
  EXPECT_LT((K6.topRightCorner<3, 3>() + S).norm(), 1e-15 * S.norm());
  EXPECT_LT((K6.bottomRightCorner<3, 3>() - S).norm(), 1e-15 * S.norm());

  // In a global K of 3 nodes (node 1 untouched), assembled from an empty pattern.
  SparseMatrix K(9, 9);
  const std::vector<NodePairSpring> springs{s};
  add_springs(springs, K);
  expect_both_triangles_stored(K);
  const Eigen::MatrixXd Kd(K);
  EXPECT_LT((Kd - Kd.transpose()).norm(), 1e-15 * Kd.norm());
  // A approaches B along n by delta: u_n = delta > 0 (compression); the spring pushes B along
  // +n with kn delta and A along -n (docs/conventions.md: force on B = +R^T k u). The spring's
  // force on the nodes is -K x.
  const double delta = 1e-6;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(9);
  x.segment<3>(0) = delta * n;
  Eigen::VectorXd f = -(Kd * x);
  EXPECT_LT((f.segment<3>(6) - 7e9 * delta * n).norm(), 1e-12 * 7e9 * delta);
  EXPECT_LT((f.segment<3>(0) + 7e9 * delta * n).norm(), 1e-12 * 7e9 * delta);
  EXPECT_EQ(f.segment<3>(3).norm(), 0.0);
  // B slides along t2 relative to A: u = R (x_A - x_B) = -delta e_t2; force on B = -kt2 delta t2.
  x.setZero();
  x.segment<3>(6) = delta * t2;
  f = -(Kd * x);
  EXPECT_LT((f.segment<3>(6) + 5e9 * delta * t2).norm(), 1e-12 * 5e9 * delta);
  // Ground spring: only K_AA.
  SparseMatrix Kg(9, 9);
  const std::vector<NodePairSpring> ground{
      {.node_a = 1, .node_b = -1, .frame = R, .k_t1 = 3e9, .k_t2 = 5e9, .k_n = 7e9}};
  add_springs(ground, Kg);
  EXPECT_EQ(Kg.nonZeros(), 9);
  EXPECT_LT((Eigen::MatrixXd(Kg).block<3, 3>(3, 3) - S).norm(), 1e-15 * S.norm());
}

TEST(Springs, AddedToAnAssembledMatrixExtendTheSparsity) {
  // Two separate hexahedra (a gap between them), joined by a spring: new A-B coupling entries.
  Mesh mesh = box_mesh(ElementType::kC3D8, 1, 1, 1, Eigen::Vector3d::Ones());
  Mesh other = box_mesh(ElementType::kC3D8, 1, 1, 1, Eigen::Vector3d::Ones());
  std::vector<int> nodes;
  for (int n = 0; n < 8; ++n) {
    nodes.push_back(mesh.add_node(100 + n, other.coordinates.col(n) + Eigen::Vector3d(2, 0, 0)));
  }
  mesh.add_element(2, ElementType::kC3D8, nodes);
  SparseMatrix K;
  assemble_stiffness_mass(mesh, kSteel, {}, &K, nullptr);
  const Eigen::MatrixXd K0(K);
  const NodePairSpring s{
      .node_a = 1, .node_b = 8, .frame = rotated_frame(), .k_t1 = 1e9, .k_t2 = 2e9, .k_n = 3e9};
  EXPECT_EQ(K0(dof_of(1, 0), dof_of(8, 0)), 0.0);
  const std::vector<NodePairSpring> springs{s};
  add_springs(springs, K);
  expect_both_triangles_stored(K);
  Eigen::MatrixXd expected = K0;
  const Eigen::Matrix<double, 6, 6> K6 = spring_stiffness(s);
  const int d[6] = {3, 4, 5, 24, 25, 26};
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) expected(d[i], d[j]) += K6(i, j);
  }
  EXPECT_LT((Eigen::MatrixXd(K) - expected).norm(), kRoundOff * expected.norm());
  // Invalid frames, nodes and stiffnesses are rejected.
  NodePairSpring bad = s;
  bad.frame(0, 0) += 1e-3;
  EXPECT_THROW(add_springs(std::vector<NodePairSpring>{bad}, K), InvalidInput);
  bad = s;
  bad.node_b = 16;
  EXPECT_THROW(add_springs(std::vector<NodePairSpring>{bad}, K), InvalidInput);
  bad = s;
  bad.k_n = -1.0;
  EXPECT_THROW(add_springs(std::vector<NodePairSpring>{bad}, K), InvalidInput);
}

}  // namespace
}  // namespace stickslip
