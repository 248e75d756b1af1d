// Consistent nodal forces of a uniform pressure (pressure_nodal_forces): hand values on a uniform
// C3D8 face grid (corner −pA/4 n, edge −pA/2 n, interior −pA n for faces of area A), the
// closed-form work-equivalent loads of an 8-node face (corners +pA/12 n, mid-edge nodes −pA/3 n),
// the outward normal on every side of a box (the resultant of a pressure on the whole closed
// surface is zero, each side's is −p S n), and the refusals.
#include "mesh/surface_area.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/errors.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"

namespace stickslip {
namespace {

constexpr double kRoundoff = 1e-12;  // relative: flat faces are integrated exactly

// Nodes of structured_hex_box with coordinate `axis` equal to `value`.
std::vector<int> nodes_where(const Mesh& mesh, int axis, double value) {
  std::vector<int> nodes;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (std::abs(mesh.coordinates(axis, n) - value) < 1e-12) nodes.push_back(n);
  }
  return nodes;
}

TEST(PressureLoads, UniformQuadGridGetsTheTributaryAreaTimesPressureAlongTheInwardNormal) {
  const int nx = 4, ny = 3, nz = 2;
  const double dx = 0.02, dy = 0.015, Lz = 0.01, p = 2.0e6;
  const Mesh mesh = structured_hex_box(nx, ny, nz, {nx * dx, ny * dy, Lz}, ElementType::kC3D8);
  const double A = dx * dy;
  for (const double z : {0.0, Lz}) {
    const std::vector<int> nodes = nodes_where(mesh, 2, z);
    const std::vector<Eigen::Vector3d> f = pressure_nodal_forces(mesh, nodes, p);
    const double inward = z == 0.0 ? 1.0 : -1.0;  // the outward normal is −z on z = 0
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < nodes.size(); ++k) {
      const double x = mesh.coordinates(0, nodes[k]), y = mesh.coordinates(1, nodes[k]);
      const int on_edges = int(std::abs(x) < 1e-12 || std::abs(x - nx * dx) < 1e-12) +
                           int(std::abs(y) < 1e-12 || std::abs(y - ny * dy) < 1e-12);
      const double a = on_edges == 2 ? A / 4 : (on_edges == 1 ? A / 2 : A);
      EXPECT_NEAR(f[k].x(), 0.0, kRoundoff * p * A);
      EXPECT_NEAR(f[k].y(), 0.0, kRoundoff * p * A);
      EXPECT_NEAR(f[k].z(), inward * p * a, kRoundoff * p * A) << x << "," << y;
      sum += f[k];
    }
    EXPECT_NEAR(sum.z(), inward * p * nx * ny * A, kRoundoff * p * nx * ny * A);
  }
}

// One 20-node hexahedron over [0, L]³, CalculiX node order (corners, then mid-edge nodes).
Mesh hex20_cube(double L) {
  const double corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                               {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                            {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  Mesh mesh;
  std::vector<Eigen::Vector3d> x;
  for (const auto& c : corner) x.emplace_back(L * c[0], L * c[1], L * c[2]);
  for (const auto& e : edges) x.push_back(0.5 * (x[e[0]] + x[e[1]]));
  std::vector<int> nodes;
  for (size_t i = 0; i < x.size(); ++i) nodes.push_back(mesh.add_node(int(i) + 1, x[i]));
  mesh.add_element(1, ElementType::kC3D20, nodes);
  return mesh;
}

TEST(PressureLoads, EightNodeFaceHasTheWorkEquivalentCornerAndMidEdgeLoads) {
  const double L = 0.03, p = 1.0e5;
  const Mesh mesh = hex20_cube(L);
  const std::vector<int> nodes = nodes_where(mesh, 0, L);  // the face x = L: 4 corners, 4 mid
  ASSERT_EQ(nodes.size(), 8u);
  const std::vector<Eigen::Vector3d> f = pressure_nodal_forces(mesh, nodes, p);
  const double A = L * L;
  for (size_t k = 0; k < nodes.size(); ++k) {
    const double y = mesh.coordinates(1, nodes[k]), z = mesh.coordinates(2, nodes[k]);
    const bool corner = (std::abs(y) < 1e-12 || std::abs(y - L) < 1e-12) &&
                        (std::abs(z) < 1e-12 || std::abs(z - L) < 1e-12);
    // ∫N dA of the serendipity face: corners −A/12, mid-edge nodes A/3; force −p ∫N dA n, n = +x.
    EXPECT_NEAR(f[k].x(), corner ? p * A / 12 : -p * A / 3, kRoundoff * p * A) << y << "," << z;
    EXPECT_NEAR(f[k].y(), 0.0, kRoundoff * p * A);
    EXPECT_NEAR(f[k].z(), 0.0, kRoundoff * p * A);
  }
}

TEST(PressureLoads, EverySideOfABoxPushesInwardAndTheClosedSurfaceHasNoResultant) {
  const Eigen::Vector3d size(0.05, 0.02, 0.03);
  const double p = 3.0e6;
  for (const ElementType type : {ElementType::kC3D8, ElementType::kC3D8I}) {
    const Mesh mesh = structured_hex_box(3, 2, 2, size, type);
    std::vector<int> surface;
    for (int axis = 0; axis < 3; ++axis) {
      for (const double value : {0.0, size(axis)}) {
        const std::vector<int> side = nodes_where(mesh, axis, value);
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (const Eigen::Vector3d& f : pressure_nodal_forces(mesh, side, p)) sum += f;
        const double S = size.prod() / size(axis);
        Eigen::Vector3d expected = Eigen::Vector3d::Zero();
        expected(axis) = value == 0.0 ? p * S : -p * S;  // inward
        EXPECT_LT((sum - expected).norm(), kRoundoff * p * S) << axis << " " << value;
        surface.insert(surface.end(), side.begin(), side.end());
      }
    }
    std::sort(surface.begin(), surface.end());
    surface.erase(std::unique(surface.begin(), surface.end()), surface.end());
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& f : pressure_nodal_forces(mesh, surface, p)) total += f;
    EXPECT_LT(total.norm(), kRoundoff * p * size.squaredNorm());
  }
}

TEST(PressureLoads, InnerFacesAndSelectionsWithoutFacesAreRefused) {
  const Mesh mesh = structured_hex_box(2, 1, 1, {0.02, 0.01, 0.01}, ElementType::kC3D8);
  // The section x = 0.01 is shared by both elements.
  try {
    pressure_nodal_forces(mesh, nodes_where(mesh, 0, 0.01), 1e5);
    FAIL() << "an inner face was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(e.message().find("shared by elements"), std::string::npos) << e.message();
  }
  const std::vector<int> two_nodes{0, 1};
  EXPECT_THROW(pressure_nodal_forces(mesh, two_nodes, 1e5), InvalidInput);
}

}  // namespace
}  // namespace stickslip
