// Nodal (tributary) areas of a surface: hand values for a uniform quadrilateral grid (corner A/4,
// edge A/2, interior A), the closed-form consistent and diagonally scaled (HRZ) values of 8-node
// and 6-node quadratic faces, and the partition-of-unity property (the nodal areas of a plane patch
// sum to its area) on a distorted seeded grid.
#include "mesh/surface_area.h"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"

namespace stickslip {
namespace {

// The rules are exact on flat faces with straight edges (Gauss degree 5 on quadrilaterals,
// degree 4 on triangles), so only rounding remains.
constexpr double kRoundoff = 1e-13;

// Nodes of structured_hex_box on the face z = size.z.
std::vector<int> top_nodes(int nx, int ny, int nz) {
  std::vector<int> nodes;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) nodes.push_back(i + (nx + 1) * (j + (ny + 1) * nz));
  }
  return nodes;
}

TEST(SurfaceArea, UniformQuadGridHasCornerQuarterEdgeHalfInteriorFullElementArea) {
  const int nx = 4, ny = 3, nz = 2;
  const double dx = 0.02, dy = 0.015;
  const Mesh mesh = structured_hex_box(nx, ny, nz, {nx * dx, ny * dy, 0.01}, ElementType::kC3D8);
  const std::vector<int> nodes = top_nodes(nx, ny, nz);
  const double A = dx * dy;  // area of one element face
  EXPECT_EQ(faces_within(mesh, nodes).size(), static_cast<size_t>(nx * ny));
  for (NodalAreaRule rule :
       {NodalAreaRule::kAutomatic, NodalAreaRule::kConsistent, NodalAreaRule::kDiagonalScaled}) {
    const std::vector<double> a = nodal_areas(mesh, nodes, rule);
    double sum = 0;
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        const int on_edges = int(i == 0 || i == nx) + int(j == 0 || j == ny);
        const double expected = on_edges == 2 ? A / 4 : (on_edges == 1 ? A / 2 : A);
        EXPECT_NEAR(a[i + (nx + 1) * j], expected, kRoundoff * A) << "node " << i << "," << j;
        sum += a[i + (nx + 1) * j];
      }
    }
    EXPECT_NEAR(sum, nx * ny * A, kRoundoff * A);
  }
}

TEST(SurfaceArea, DistortedPlanePatchAreasSumToItsArea) {
  // Interior nodes of the top face moved in the plane (seeded): the patch keeps its rectangular
  // outline, so the nodal areas must still sum to Lx·Ly, and every node keeps a positive area.
  const int nx = 5, ny = 4, nz = 1;
  const double Lx = 0.1, Ly = 0.06;
  Mesh mesh = structured_hex_box(nx, ny, nz, {Lx, Ly, 0.02}, ElementType::kC3D8);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> shift(-0.3, 0.3);
  for (int j = 1; j < ny; ++j) {
    for (int i = 1; i < nx; ++i) {
      const int n = i + (nx + 1) * (j + (ny + 1) * nz);
      mesh.coordinates(0, n) += shift(rng) * Lx / nx;
      mesh.coordinates(1, n) += shift(rng) * Ly / ny;
    }
  }
  const std::vector<int> nodes = top_nodes(nx, ny, nz);
  for (NodalAreaRule rule : {NodalAreaRule::kConsistent, NodalAreaRule::kDiagonalScaled}) {
    const std::vector<double> a = nodal_areas(mesh, nodes, rule);
    double sum = 0;
    for (double v : a) {
      EXPECT_GT(v, 0.0);
      sum += v;
    }
    EXPECT_NEAR(sum, Lx * Ly, kRoundoff * Lx * Ly);
  }
  double faces = 0;
  for (const ElementFace& f : faces_within(mesh, nodes)) faces += face_area(mesh, f);
  EXPECT_NEAR(faces, Lx * Ly, kRoundoff * Lx * Ly);
}

// One 20-node hexahedron over [0, a] x [0, b] x [0, c], CalculiX node order.
Mesh hex20_box(double a, double b, double c) {
  const double corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                               {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                            {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  Mesh mesh;
  std::vector<Eigen::Vector3d> x;
  for (const auto& p : corner) x.emplace_back(a * p[0], b * p[1], c * p[2]);
  for (const auto& e : edges) x.push_back(0.5 * (x[e[0]] + x[e[1]]));
  std::vector<int> nodes;
  for (size_t i = 0; i < x.size(); ++i) nodes.push_back(mesh.add_node(int(i) + 1, x[i]));
  mesh.add_element(1, ElementType::kC3D20, nodes);
  return mesh;
}

TEST(SurfaceArea, SerendipityFaceConsistentCornersAreNegativeScaledArePositive) {
  const double a = 0.03, b = 0.02;
  const Mesh mesh = hex20_box(a, b, 0.01);
  // Face z = c: corners 4..7 and mid-edge nodes 12..15.
  const std::vector<int> nodes{4, 5, 6, 7, 12, 13, 14, 15};
  const double A = a * b;
  ASSERT_EQ(faces_within(mesh, nodes).size(), 1u);
  const std::vector<double> consistent = nodal_areas(mesh, nodes, NodalAreaRule::kConsistent);
  const std::vector<double> scaled = nodal_areas(mesh, nodes, NodalAreaRule::kDiagonalScaled);
  const std::vector<double> automatic = nodal_areas(mesh, nodes);
  for (int k = 0; k < 8; ++k) {
    const bool corner = k < 4;
    // ∫N dA of the 8-node serendipity rectangle: −A/12 at corners, A/3 at mid-edge nodes.
    EXPECT_NEAR(consistent[k], corner ? -A / 12 : A / 3, kRoundoff * A);
    // HRZ: A ∫N_i² / Σ∫N_j²: 3A/76 at corners, 16A/76 at mid-edge nodes.
    EXPECT_NEAR(scaled[k], corner ? 3 * A / 76 : 16 * A / 76, kRoundoff * A);
    EXPECT_EQ(automatic[k], scaled[k]);
  }
}

TEST(SurfaceArea, TriangleFacesOfTetrahedra) {
  // Face (0, 1, 2) of a tetrahedron lies in z = 0: a right triangle of legs a, b.
  const double a = 0.04, b = 0.03, A = 0.5 * a * b;
  const std::array<Eigen::Vector3d, 4> corners{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(a, 0, 0),
                                               Eigen::Vector3d(0, b, 0),
                                               Eigen::Vector3d(0, 0, 0.02)};
  {
    Mesh tet4;
    std::vector<int> n;
    for (int i = 0; i < 4; ++i) n.push_back(tet4.add_node(i + 1, corners[i]));
    tet4.add_element(1, ElementType::kC3D4, n);
    const std::vector<int> face{0, 1, 2};
    for (double v : nodal_areas(tet4, face)) EXPECT_NEAR(v, A / 3, kRoundoff * A);
  }
  Mesh tet10;
  const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  std::vector<int> n;
  for (int i = 0; i < 4; ++i) n.push_back(tet10.add_node(i + 1, corners[i]));
  for (int e = 0; e < 6; ++e) {
    n.push_back(tet10.add_node(5 + e, 0.5 * (corners[edges[e][0]] + corners[edges[e][1]])));
  }
  tet10.add_element(1, ElementType::kC3D10, n);
  const std::vector<int> face{0, 1, 2, 4, 5, 6};  // corners, then mid-edge nodes
  const auto consistent = nodal_areas(tet10, face, NodalAreaRule::kConsistent);
  const auto automatic = nodal_areas(tet10, face);
  for (int k = 0; k < 6; ++k) {
    const bool corner = k < 3;
    // ∫N dA of the 6-node triangle: 0 at corners, A/3 at mid-edge nodes.
    EXPECT_NEAR(consistent[k], corner ? 0.0 : A / 3, kRoundoff * A);
    // HRZ: 3A/57 at corners, 16A/57 at mid-edge nodes.
    EXPECT_NEAR(automatic[k], corner ? 3 * A / 57 : 16 * A / 57, kRoundoff * A);
  }
}

TEST(SurfaceArea, SharedFaceCountsOnceAndNodesOffTheSurfaceGetZero) {
  // Two elements stacked along z share the face z = 0.01; select it plus one node of the bottom.
  const Mesh mesh = structured_hex_box(1, 1, 2, {0.02, 0.03, 0.02}, ElementType::kC3D8);
  const std::vector<int> nodes{4, 5, 6, 7, 0};  // k = 1 layer, then a bottom corner
  EXPECT_EQ(faces_within(mesh, nodes).size(), 1u);
  const std::vector<double> a = nodal_areas(mesh, nodes);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(a[k], 0.02 * 0.03 / 4, kRoundoff * 6e-4);
  EXPECT_EQ(a[4], 0.0);
}

}  // namespace
}  // namespace stickslip
